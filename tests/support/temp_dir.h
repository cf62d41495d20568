#pragma once
// A fresh temporary folder that removes itself, and a fixture giving each test one. Names carry
// the process id and a counter: ctest runs every test case in its own process, in parallel.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <string>

namespace vknerf::test {

class TempDir {
 public:
  // <system temp>/vknerf_<tag>_<pid>_<n>, empty.
  explicit TempDir(const std::string& tag);
  ~TempDir();  // removes the folder and all it holds
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // path() / name, as the string the file APIs and the command line take.
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// A TempDir per test, named after the test.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override { dir_.reset(); }
  const std::filesystem::path& dir() const { return dir_->path(); }

 private:
  std::unique_ptr<TempDir> dir_;
};

}  // namespace vknerf::test

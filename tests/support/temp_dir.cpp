#include "support/temp_dir.h"

#include <unistd.h>

#include <atomic>

namespace vknerf::test {

namespace fs = std::filesystem;

TempDir::TempDir(const std::string& tag) {
  static std::atomic<unsigned> counter{0};
  path_ = fs::temp_directory_path() /
          ("vknerf_" + tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  fs::remove_all(path_);  // a leftover of a crashed run with a recycled pid
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;  // never throw from a destructor; a leftover folder is harmless
  fs::remove_all(path_, ec);
}

void TempDirTest::SetUp() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  dir_ = std::make_unique<TempDir>(std::string(info->test_suite_name()) + "_" + info->name());
}

}  // namespace vknerf::test

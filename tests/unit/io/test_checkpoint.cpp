// Checkpoint container: round trip, atomic replacement, and every way a file can be bad.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "io/checkpoint/checkpoint.h"
#include "lib/metrics.h"
#include "support/temp_dir.h"
#include "vknerf/error.h"

using namespace vknerf;
namespace fs = std::filesystem;

namespace {

io::Checkpoint sample() {
  io::Checkpoint ck;
  ck.config = R"({"model":"vanilla","step":1234})";
  ck.put("params", std::vector<float>{1.5f, -2.0f, 3.25f});
  ck.put("adam_m", std::vector<float>(1000, 0.125f));
  ck.put("occupancy", std::vector<uint32_t>{0xdeadbeef});
  return ck;
}

std::string errorOf(const std::string& path) {
  try {
    io::Checkpoint::load(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Checkpoint, RoundTrip) {
  const test::TempDir tmp("checkpoint");
  const auto path = tmp.file("a.vknerf");
  sample().save(path);
  auto ck = io::Checkpoint::load(path);
  EXPECT_EQ(ck.config, sample().config);
  EXPECT_EQ(ck.get<float>("params", 3), (std::vector<float>{1.5f, -2.0f, 3.25f}));
  EXPECT_EQ(ck.get<float>("adam_m").size(), 1000u);
  EXPECT_EQ(ck.get<uint32_t>("occupancy")[0], 0xdeadbeefu);
  EXPECT_FALSE(fs::exists(path + ".tmp." + std::to_string(::getpid())));
}

TEST(Checkpoint, SaveReplacesAtomically) {
  const test::TempDir tmp("checkpoint");
  const auto path = tmp.file("b.vknerf");
  sample().save(path);
  auto ck = sample();
  ck.config = R"({"step":9})";
  ck.save(path);
  EXPECT_EQ(io::Checkpoint::load(path).config, R"({"step":9})");
}

TEST(Checkpoint, MissingFileNamesThePath) {
  auto msg = errorOf("/nonexistent/dir/model.vknerf");
  EXPECT_NE(msg.find("/nonexistent/dir/model.vknerf"), std::string::npos) << msg;
}

TEST(Checkpoint, TruncatedFileIsRejected) {
  const test::TempDir tmp("checkpoint");
  const auto path = tmp.file("c.vknerf");
  sample().save(path);
  auto size = fs::file_size(path);
  for (auto cut : {size - 1, size / 2, uintmax_t(10), uintmax_t(3)}) {
    fs::resize_file(path, cut);
    auto msg = errorOf(path);
    EXPECT_FALSE(msg.empty()) << "cut at " << cut;
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    sample().save(path);
    size = fs::file_size(path);
  }
}

TEST(Checkpoint, CorruptByteFailsChecksum) {
  const test::TempDir tmp("checkpoint");
  const auto path = tmp.file("d.vknerf");
  sample().save(path);
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(40);
  f.put('\x7f');
  f.close();
  EXPECT_NE(errorOf(path).find("corrupt"), std::string::npos) << errorOf(path);
}

TEST(Checkpoint, WrongVersionAndMagicAreNamed) {
  const test::TempDir tmp("checkpoint");
  const auto path = tmp.file("e.vknerf");
  sample().save(path);
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(8);
    uint32_t v = 99;
    f.write(reinterpret_cast<char*>(&v), 4);
  }
  EXPECT_NE(errorOf(path).find("version 99"), std::string::npos) << errorOf(path);
  std::ofstream(path) << "hello, not a checkpoint";
  EXPECT_NE(errorOf(path).find("magic"), std::string::npos) << errorOf(path);
}

TEST(Checkpoint, MissingOrMissizedSectionIsNamed) {
  const test::TempDir tmp("checkpoint");
  const auto path = tmp.file("f.vknerf");
  sample().save(path);
  auto ck = io::Checkpoint::load(path);
  EXPECT_THROW(ck.get<float>("nope"), Error);
  try {
    ck.get<float>("params", 4);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("params"), std::string::npos);
  }
}

TEST(Metrics, PsnrOfKnownError) {
  std::vector<float> a(300, 0.5f), b(300, 0.6f);  // mse 0.01 -> 20 dB
  EXPECT_NEAR(nerf::psnr(a, b), 20.0, 1e-4);
  EXPECT_EQ(nerf::psnr(a, a), 100.0);
}

TEST(Metrics, SsimIdentityAndDegradation) {
  const uint32_t w = 32, h = 24;
  std::vector<float> img(w * h * 3), noisy(img.size()), flat(img.size(), 0.5f);
  for (size_t i = 0; i < img.size(); ++i) {
    img[i] = float((i * 7919) % 101) / 100.0f;
    noisy[i] = std::clamp(img[i] + ((i % 3) ? 0.1f : -0.1f), 0.0f, 1.0f);
  }
  EXPECT_NEAR(nerf::ssim(img, img, w, h), 1.0, 1e-9);
  double sn = nerf::ssim(img, noisy, w, h), sf = nerf::ssim(img, flat, w, h);
  EXPECT_LT(sn, 0.999);
  EXPECT_LT(sf, sn);  // a constant image keeps none of the structure
  EXPECT_THROW(nerf::ssim(img, flat, w + 1, h), Error);
}

TEST(Checkpoint, ParseFromMemoryMatchesLoad) {
  const test::TempDir tmp("checkpoint");
  auto path = tmp.file("memory.vknerf");
  sample().save(path);
  std::ifstream in(path, std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto ck = io::Checkpoint::parse(bytes.data(), bytes.size(), "in memory");
  EXPECT_EQ(ck.config, sample().config);
  EXPECT_EQ(ck.sections, sample().sections);
  EXPECT_EQ(ck.path, "in memory");
  try {
    io::Checkpoint::parse(bytes.data(), bytes.size() - 1, "in memory");
    ADD_FAILURE() << "a truncated checkpoint parsed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("in memory"), std::string::npos) << e.what();
  }
}

// Datasets of any size: training pixels spread over several bindings train like one, frames of
// different sizes load and train, a dataset that cannot fit is refused before anything is
// allocated, and images decoded in parallel are the serial ones byte for byte.
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include "nerf/loss/pixel_bindings.h"
#include "support/dataset_files.h"
#include "support/error_message.h"
#include "support/gpu_test.h"
#include "support/sample_scene.h"
#include "support/temp_dir.h"
#include "support/tiny_config.h"
#include "vknerf/error.h"
#include "vknerf/trainer.h"

using namespace vknerf;
using namespace vknerf::test;

namespace {

TrainConfig tinyConfig() { return test::tinyVanillaConfig(); }

const Dataset& tabletop() { return test::quarterSizeSampleScene(); }

// Lowers the device's limits for one test, restoring them after.
struct LimitsFor {
  explicit LimitsFor(nerf::PixelStorageLimits l) : saved(nerf::pixelStorageLimits()) { nerf::pixelStorageLimits() = l; }
  ~LimitsFor() { nerf::pixelStorageLimits() = saved; }
  nerf::PixelStorageLimits saved;
};

std::vector<double> losses(const Dataset& data, int steps) {
  Trainer t(sharedContext(), data, tinyConfig());
  std::vector<double> out;
  for (int i = 0; i < steps; ++i) out.push_back(t.step(true).loss);
  return out;
}

class LargeDatasets : public GpuTest {};
class DecodeTest : public TempDirTest {};

}  // namespace

TEST(PixelBindingPlan, ImagesNeverStraddleBindings) {
  const std::vector<uint64_t> counts = {10, 20, 5, 30, 1, 32};
  auto l = nerf::planPixelBindings(counts, 32 * 4);  // 32 pixels per binding
  ASSERT_EQ(l.images.size(), counts.size());
  EXPECT_EQ(l.totalPixels, 98u);
  const std::vector<std::pair<uint32_t, uint32_t>> want = {{0, 0}, {0, 10}, {1, 0}, {2, 0}, {2, 30}, {3, 0}};
  for (size_t i = 0; i < counts.size(); ++i) {
    EXPECT_EQ(l.images[i].binding, want[i].first) << i;
    EXPECT_EQ(l.images[i].firstPixel, want[i].second) << i;
    EXPECT_LE(l.images[i].firstPixel + counts[i], 32u) << i;
  }
  EXPECT_EQ(l.bindingPixels, (std::vector<uint64_t>{30, 5, 31, 32}));
  EXPECT_THROW(nerf::planPixelBindings(std::vector<uint64_t>{33}, 32 * 4), Error);
}

// Bit-identical per-ray gradients whatever the binding count, so the same trajectory; only the
// loss's summation over the loss kernel's dispatches may round differently.
TEST_F(LargeDatasets, PixelsOverManyBindingsTrainLikeOne) {
  const auto one = losses(tabletop(), 4);
  std::vector<double> many;
  {
    const uint64_t imageBytes = tabletop().images[0].rgba.size();
    LimitsFor limits({.bytesPerBinding = imageBytes + imageBytes / 2});  // one image per binding
    Trainer t(sharedContext(), tabletop(), tinyConfig());
    EXPECT_EQ(t.trainingPixelBindings(), tabletop().images.size());
    EXPECT_GT(t.trainingPixelBindings(), 8u);  // the loss kernel takes more than one dispatch
    for (int i = 0; i < 4; ++i) many.push_back(t.step(true).loss);
  }
  for (size_t i = 0; i < one.size(); ++i) EXPECT_NEAR(many[i], one[i], 1e-6 * one[i]) << "step " << i;
}

TEST_F(LargeDatasets, TooLargeForTheDeviceIsOneClearError) {
  uint64_t model = 0, pixels = 0;
  {
    Trainer t(sharedContext(), tabletop(), tinyConfig());
    model = uint64_t(std::llround(t.statistics().deviceMiB * (1 << 20)));
    pixels = uint64_t(std::llround(t.trainingPixelsDeviceMiB() * (1 << 20)));
  }
  // Room for the model and half the pixels: a quarter of them (downscale 2) would fit.
  LimitsFor limits({.deviceBytes = model + pixels / 2});
  const std::string m = errorOf([&] { Trainer t(sharedContext(), tabletop(), tinyConfig()); });
  EXPECT_MESSAGE_HAS(m, "training needs");
  EXPECT_MESSAGE_HAS(m, "model: ");
  EXPECT_MESSAGE_HAS(m, "2 times the current --downscale would fit");
  // With no room even for the model, no downscale helps, and the message says so.
  nerf::pixelStorageLimits().deviceBytes = model / 2;
  EXPECT_MESSAGE_HAS(errorOf([&] { Trainer t(sharedContext(), tabletop(), tinyConfig()); }), "no --downscale");
}

TEST_F(DecodeTest, MixedResolutionFramesLoadAndTrain) {
  json fr = json::array();
  const uint32_t sizes[4][2] = {{24, 18}, {40, 30}, {16, 16}, {30, 20}};
  for (int i = 0; i < 4; ++i) {
    const double a = 2 * M_PI * i / 4;
    const std::string name = "images/f" + std::to_string(i);
    writePng(dir() / (name + ".png"), patternImage(sizes[i][0], sizes[i][1], uint32_t(i)));
    fr.push_back({{"file_path", "./" + name}, {"w", sizes[i][0]}, {"h", sizes[i][1]}, {"fl_x", 0.9 * sizes[i][0]},
                  {"transform_matrix", matrixJson(poseLookingAt({3 * std::cos(a), 3 * std::sin(a), 1.5}, {0, 0, 0}))}});
  }
  writeJson(dir() / "transforms.json", json{{"frames", fr}, {"aabb", {{-1, -1, -1}, {1, 1, 1}}}});
  Dataset d = Dataset::load(dir().string(), {.split = "all"});
  ASSERT_EQ(d.images.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(d.images[i].width, sizes[i][0]);
    EXPECT_EQ(d.cameras[i].height, sizes[i][1]);
  }
  LimitsFor limits({.bytesPerBinding = 40 * 30 * 4});  // the largest image fills a binding
  Trainer t(sharedContext(), d, tinyConfig());
  EXPECT_EQ(t.trainingPixelBindings(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(t.step(true).loss));
}

TEST_F(DecodeTest, ParallelDecodeIsSerialByteForByteAndNamesABadFile) {
  json fr = json::array();
  for (int i = 0; i < 9; ++i) {
    const std::string name = "images/f" + std::to_string(i);
    writePng(dir() / (name + ".png"), patternImage(20 + i, 12 + i, uint32_t(i), i % 2 == 0));
    fr.push_back({{"file_path", "./" + name}, {"fl_x", 20.0},
                  {"transform_matrix", matrixJson(poseLookingAt({3.0 + i, 1, 1}, {0, 0, 0}))}});
  }
  writeJson(dir() / "transforms.json", json{{"frames", fr}, {"aabb", {{-1, -1, -1}, {1, 1, 1}}}});
  size_t calls = 0, lastDone = 0;
  Dataset serial = Dataset::load(dir().string(), {.split = "all", .threads = 1});
  Dataset parallel = Dataset::load(dir().string(), {.split = "all", .threads = 4, .progress = [&](size_t done, size_t total) {
                                                     EXPECT_EQ(total, 9u);
                                                     EXPECT_EQ(done, lastDone + 1);
                                                     lastDone = done;
                                                     ++calls;
                                                   }});
  EXPECT_EQ(calls, 9u);
  ASSERT_EQ(serial.images.size(), parallel.images.size());
  for (size_t i = 0; i < serial.images.size(); ++i) {
    EXPECT_EQ(serial.images[i].width, parallel.images[i].width);
    EXPECT_EQ(serial.images[i].rgba, parallel.images[i].rgba) << i;
  }
  // A file whose header reads but whose data is cut short fails in a decoding thread: the error
  // names that file.
  const auto bad = dir() / "images/f5.png";
  std::string bytes;
  {
    std::ifstream in(bad, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(bad, std::ios::binary | std::ios::trunc).write(bytes.data(), 60);
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::load(dir().string(), {.split = "all", .threads = 4}); }), "f5.png");
}

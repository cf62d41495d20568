// The spectral-bias experiment (seed §2.8, §6.7) end to end on the device: MLP forward/backward,
// frequency encoding, photometric loss and Adam fit a small image with sharp detail.
#include <cmath>
#include <vector>

#include "support/gpu_test.h"
#include "kernels/fit_image.h"

using namespace vknerf;

namespace {

// 64x64: a checkerboard of 4-pixel cells (8 cycles across: detail a raw-coordinate MLP learns only
// very late) in two colours, with a smooth green disc over it.
std::vector<uint32_t> sharpImage(uint32_t size) {
  std::vector<uint32_t> px(size * size);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x) {
      bool cell = ((x / 4) + (y / 4)) % 2;
      float r = cell ? 0.9f : 0.1f, g = 0.25f, b = cell ? 0.15f : 0.8f;
      float dx = float(x) - 40.0f, dy = float(y) - 24.0f;
      if (dx * dx + dy * dy < 120.0f) r = 0.2f, g = 0.85f, b = 0.3f;
      auto q = [](float v) { return uint32_t(v * 255.0f + 0.5f); };
      px[y * size + x] = q(r) | q(g) << 8 | q(b) << 16 | 0xffu << 24;
    }
  return px;
}

class MlpFitImage : public test::GpuTest {};

}  // namespace

TEST_F(MlpFitImage, EncodingBeatsRawCoordinatesByFiveDecibels) {
  const uint32_t size = 64;
  auto image = sharpImage(size);
  nerf::FitImageConfig cfg;
  cfg.steps = 100;
  cfg.width = 64;
  cfg.learningRate = 5e-3f;
  cfg.seed = 3;
  cfg.encoding = true;
  auto encoded = nerf::fitImage(ctx(), image, size, size, cfg);
  cfg.encoding = false;
  auto raw = nerf::fitImage(ctx(), image, size, size, cfg);
  std::printf("PSNR after %u steps: encoded %.2f dB, raw %.2f dB\n", cfg.steps, encoded.psnr, raw.psnr);
  for (float v : encoded.rgb) ASSERT_TRUE(std::isfinite(v));
  EXPECT_GE(encoded.psnr, raw.psnr + 5.0);
  EXPECT_GT(encoded.psnr, 20.0);  // and the encoded fit is a real fit, not two failures
}

#pragma once
// Per-ray background colours (shaders/loss/random_background.comp): the colour the photometric
// loss composites behind each ray, one vec4 (r, g, b, 1) per ray.
#include <array>
#include <cstdint>

#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"

namespace vknerf::nerf {

class BackgroundColors {
 public:
  explicit BackgroundColors(Context& ctx);
  // background[i] = (rng01(seed, i, 100), rng01(seed, i, 101), rng01(seed, i, 102), 1).
  void recordRandom(gpu::Recorder& rec, const gpu::BufferRange& background, uint32_t numRays, uint32_t seed);
  // background[i] = (rgb, 1).
  void recordConstant(gpu::Recorder& rec, const gpu::BufferRange& background, uint32_t numRays,
                      const std::array<float, 3>& rgb);

 private:
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

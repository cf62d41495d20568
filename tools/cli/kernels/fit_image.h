#pragma once
// The seed's spectral-bias experiment (§2.8, §6.7): fit one image as a function (u, v) -> rgb with a
// plain MLP, with or without the frequency encoding gamma(u, v), by full-batch Adam on the MSE.
// Every pixel is one row of every step; the whole step (MLP forward, loss, MLP backward, Adam) is one
// command buffer.
#include <cstdint>
#include <functional>
#include <vector>

#include "vknerf/context.h"

namespace vknerf::nerf {

struct FitImageConfig {
  uint32_t steps = 2000;
  bool encoding = true;   // gamma(u, v) with `levels` octaves plus the raw (u, v); else raw (u, v)
  uint32_t levels = 10;
  uint32_t width = 128;   // seed §6.7: 2 hidden layers of 128
  uint32_t hiddenLayers = 2;
  float learningRate = 1e-3f;
  uint32_t seed = 0;
};

struct FitImageResult {
  std::vector<float> rgb;  // the fitted image, 3 floats per pixel, row-major
  double psnr = 0;         // of the fitted image against the target, dB
};

// rgba8: width*height pixels, R in the low byte (alpha is ignored: the target is the rgb).
// progress(step, trainingMse) is called every `progressEvery` steps (0: never).
FitImageResult fitImage(Context& ctx, const std::vector<uint32_t>& rgba8, uint32_t width, uint32_t height,
                        const FitImageConfig& config, uint32_t progressEvery = 0,
                        const std::function<void(uint32_t, double)>& progress = {});

}  // namespace vknerf::nerf

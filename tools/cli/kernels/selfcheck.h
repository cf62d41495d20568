#pragma once
// End-to-end check of the rendering kernels without a trained network: an analytic field
// (shaders/selfcheck/field_analytic.comp) is rendered through rays -> stratified samples -> points -> field
// -> compositing -> inverse-CDF samples -> field -> compositing, on the device and in the double
// CPU reference, and the images are compared.
#include <string>
#include <utility>
#include <vector>

#include "vknerf/context.h"

namespace vknerf::nerf {

struct SelfCheckResult {
  uint32_t width = 0, height = 0;
  std::vector<float> rgb, referenceRgb;  // 3 per pixel
  double maxColorError = 0, maxOpacityError = 0, maxDepthError = 0;
  std::vector<std::pair<std::string, double>> kernelMilliseconds;  // device timestamps per stage
};

SelfCheckResult selfCheck(Context& ctx, uint32_t size = 64, uint32_t coarse = 64, uint32_t fine = 64);

}  // namespace vknerf::nerf

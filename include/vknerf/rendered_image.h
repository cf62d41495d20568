#pragma once
// A view rendered on the host (Model::render): colour, depth, opacity and the background behind it.
#include <cstdint>
#include <vector>

#include "vknerf/kernel_times.h"

namespace vknerf {

struct RenderedImage {
  uint32_t width = 0, height = 0;
  std::vector<float> rgb;      // 3 per pixel, composited over the background
  std::vector<float> depth;    // expected depth sum w_i t_i / opacity (0 where opacity is ~0)
  std::vector<float> opacity;  // 1 - T_final
  // 3 per pixel: the colour behind the field that rgb is composited over (a learned far field's
  // colour in the pixel's direction, else the constant background); empty in images made by hand.
  std::vector<float> background;
  // Field samples shaded to render it (Model::render; 0 in images made by hand): over the pixels,
  // the samples per ray a render spends, where early termination ends most rays short of the cap.
  uint64_t samples = 0;
  // With RenderSettings::profile: device milliseconds per kernel, summed over the render's
  // dispatches of it, in the order each was first recorded; empty when not profiled, or on a device
  // whose compute queue has no timestamps.
  KernelTimes kernelMs;
};

}  // namespace vknerf

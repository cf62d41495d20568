#pragma once
// Writing rendered views: RGB and opacity as PNG, depth as a colour-mapped PNG and as raw 32-bit
// floats (PFM, readable by most image tools and numpy in a few lines).
#include <string>

#include "vknerf/trainer.h"

namespace vknerf::nerf {

void saveRgbPng(const std::string& path, const RenderedImage& img);
void saveOpacityPng(const std::string& path, const RenderedImage& img);
// Depth mapped with a perceptual colour map over [nearDepth, farDepth]; transparent pixels black.
void saveDepthPng(const std::string& path, const RenderedImage& img, float nearDepth, float farDepth);
void saveDepthPfm(const std::string& path, const RenderedImage& img);

}  // namespace vknerf::nerf

#pragma once
// Writing rendered views: RGB and opacity as PNG, depth as a colour-mapped PNG and as raw 32-bit
// floats (PFM, readable by most image tools and numpy in a few lines).
#include <string>

#include "vknerf/dataset.h"
#include "vknerf/trainer.h"

namespace vknerf::nerf {

// The rendered colour as 8-bit RGBA (alpha 255): what the PNG and the video frames hold.
ImageRGBA8 rgbaOf(const RenderedImage& img);
void saveRgbPng(const std::string& path, const RenderedImage& img);
void saveOpacityPng(const std::string& path, const RenderedImage& img);
// Depth mapped with a perceptual colour map over [nearDepth, farDepth]; transparent pixels black.
void saveDepthPng(const std::string& path, const RenderedImage& img, float nearDepth, float farDepth);
void saveDepthPfm(const std::string& path, const RenderedImage& img);

}  // namespace vknerf::nerf

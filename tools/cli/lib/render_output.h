#pragma once
// Writing rendered views: RGB and opacity as PNG, depth as a colour-mapped PNG and as raw 32-bit
// floats (PFM, readable by most image tools and numpy in a few lines).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vknerf/dataset.h"
#include "vknerf/trainer.h"

namespace vknerf::nerf {

// The rendered colour as 8-bit RGBA (alpha 255): what the PNG and the video frames hold.
ImageRGBA8 rgbaOf(const RenderedImage& img);
void saveRgbPng(const std::string& path, const RenderedImage& img);
void saveOpacityPng(const std::string& path, const RenderedImage& img);
// The perceptual colour map of the depth images (dark blue -> teal -> yellow) at t in [0, 1]
// (clamped); NaN is black. Also the error map of eval's contact sheet.
std::array<uint8_t, 3> mapColour(float t);
// The depth range the colour map spans for cameras at `cameraDistance` from the origin, looking at
// `box`: the box's diagonal either side of that distance, from 0 at the nearest.
struct DepthRange {
  float nearDepth = 0, farDepth = 1;
};
DepthRange depthRangeFor(float cameraDistance, const Aabb& box);
// The range the depths of these views' opaque pixels (opacity >= 0.5) span, from their
// `share`-quantile to their (1 - share)-quantile: a sheet of a few views reads its depths over what
// they hold, where depthRangeFor's box may be a room around a cup. Empty when no pixel is opaque.
std::optional<DepthRange> depthRangeOfOpaquePixels(const std::vector<const RenderedImage*>& views, float share = 0.01f);
// The cameras' mean distance from the origin (0 for none): orbits and depth ranges centre on it.
float meanCameraDistance(const std::vector<Camera>& cameras);
// Depth mapped with the colour map over [nearDepth, farDepth]; transparent pixels black.
ImageRGBA8 depthRgba(const RenderedImage& img, float nearDepth, float farDepth);
void saveDepthPng(const std::string& path, const RenderedImage& img, float nearDepth, float farDepth);
void saveDepthPfm(const std::string& path, const RenderedImage& img);

}  // namespace vknerf::nerf

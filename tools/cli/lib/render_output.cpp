#include "lib/render_output.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "vknerf/image_io.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"

namespace vknerf::nerf {
namespace {

uint8_t toByte(float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

}  // namespace

// A compact perceptual map (dark blue -> teal -> yellow), piecewise linear through 5 stops. A NaN
// (an unknown depth, or a depth range that is not finite) is drawn black like empty space: it must
// never reach the stop index, where int(NaN) is undefined.
std::array<uint8_t, 3> mapColour(float t) {
  static const float stops[5][3] = {{0.05f, 0.03f, 0.35f}, {0.15f, 0.35f, 0.60f}, {0.15f, 0.60f, 0.55f},
                                    {0.55f, 0.80f, 0.25f}, {0.99f, 0.91f, 0.15f}};
  if (std::isnan(t)) return {0, 0, 0};
  t = std::clamp(t, 0.0f, 1.0f) * 4.0f;
  int i = std::min(int(t), 3);
  float f = t - float(i);
  std::array<uint8_t, 3> rgb;
  for (int k = 0; k < 3; ++k) rgb[k] = toByte(stops[i][k] * (1 - f) + stops[i + 1][k] * f);
  return rgb;
}

float meanCameraDistance(const std::vector<Camera>& cameras) {
  float sum = 0;
  for (const Camera& c : cameras) sum += std::sqrt(c.c2w[3] * c.c2w[3] + c.c2w[7] * c.c2w[7] + c.c2w[11] * c.c2w[11]);
  return cameras.empty() ? 0.0f : sum / float(cameras.size());
}

DepthRange depthRangeFor(float cameraDistance, const Aabb& b) {
  const float diag = std::sqrt((b.max[0] - b.min[0]) * (b.max[0] - b.min[0]) + (b.max[1] - b.min[1]) * (b.max[1] - b.min[1]) +
                               (b.max[2] - b.min[2]) * (b.max[2] - b.min[2]));
  return {std::max(cameraDistance - 0.5f * diag, 0.0f), cameraDistance + 0.5f * diag};
}

std::optional<DepthRange> depthRangeOfOpaquePixels(const std::vector<const RenderedImage*>& views, float share) {
  std::vector<float> depths;
  for (const RenderedImage* v : views)
    for (size_t p = 0; p < v->depth.size() && p < v->opacity.size(); ++p)
      if (v->opacity[p] >= 0.5f && std::isfinite(v->depth[p])) depths.push_back(v->depth[p]);
  if (depths.empty()) return std::nullopt;
  const auto at = [&](float q) {
    const size_t k = std::min(depths.size() - 1, size_t(q * float(depths.size() - 1) + 0.5f));
    std::nth_element(depths.begin(), depths.begin() + k, depths.end());
    return depths[k];
  };
  const float nearDepth = at(share), farDepth = at(1.0f - share);
  return DepthRange{nearDepth, std::max(farDepth, nearDepth + 1e-6f)};
}

ImageRGBA8 rgbaOf(const RenderedImage& img) {
  ImageRGBA8 out{img.width, img.height, std::vector<uint8_t>(size_t(img.width) * img.height * 4, 255)};
  for (size_t p = 0; p < size_t(img.width) * img.height; ++p)
    for (int k = 0; k < 3; ++k) out.rgba[p * 4 + k] = toByte(img.rgb[p * 3 + k]);
  return out;
}

void saveRgbPng(const std::string& path, const RenderedImage& img) { savePng(path, rgbaOf(img)); }

void saveOpacityPng(const std::string& path, const RenderedImage& img) {
  ImageRGBA8 out{img.width, img.height, std::vector<uint8_t>(size_t(img.width) * img.height * 4, 255)};
  for (size_t p = 0; p < size_t(img.width) * img.height; ++p)
    for (int k = 0; k < 3; ++k) out.rgba[p * 4 + k] = toByte(img.opacity[p]);
  savePng(path, out);
}

ImageRGBA8 depthRgba(const RenderedImage& img, float nearDepth, float farDepth) {
  ImageRGBA8 out{img.width, img.height, std::vector<uint8_t>(size_t(img.width) * img.height * 4, 255)};
  const float span = std::max(farDepth - nearDepth, 1e-6f);
  for (size_t p = 0; p < size_t(img.width) * img.height; ++p) {
    const auto rgb = img.opacity[p] < 0.5f ? std::array<uint8_t, 3>{0, 0, 0} : mapColour((img.depth[p] - nearDepth) / span);
    std::copy(rgb.begin(), rgb.end(), &out.rgba[p * 4]);
  }
  return out;
}

void saveDepthPng(const std::string& path, const RenderedImage& img, float nearDepth, float farDepth) {
  savePng(path, depthRgba(img, nearDepth, farDepth));
}

void saveDepthPfm(const std::string& path, const RenderedImage& img) {
  // PFM: greyscale "Pf", negative scale = little-endian, rows bottom to top.
  std::string pfm = "Pf\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n-1.0\n";
  const size_t header = pfm.size(), row = size_t(img.width) * 4;
  pfm.resize(header + row * img.height);
  for (uint32_t y = 0; y < img.height; ++y)
    std::memcpy(&pfm[header + size_t(img.height - 1 - y) * row], &img.depth[size_t(y) * img.width], row);
  writeFileAtomically(path, pfm);
}

}  // namespace vknerf::nerf

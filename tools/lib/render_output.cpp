#include "lib/render_output.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "io/image_io.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"

namespace vknerf::nerf {
namespace {

uint8_t toByte(float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

// A compact perceptual map (dark blue -> teal -> yellow), piecewise linear through 5 stops. A NaN
// (an unknown depth, or a depth range that is not finite) is drawn black like empty space: it must
// never reach the stop index, where int(NaN) is undefined.
void colormap(float t, uint8_t* rgb) {
  static const float stops[5][3] = {{0.05f, 0.03f, 0.35f}, {0.15f, 0.35f, 0.60f}, {0.15f, 0.60f, 0.55f},
                                    {0.55f, 0.80f, 0.25f}, {0.99f, 0.91f, 0.15f}};
  if (std::isnan(t)) {
    rgb[0] = rgb[1] = rgb[2] = 0;
    return;
  }
  t = std::clamp(t, 0.0f, 1.0f) * 4.0f;
  int i = std::min(int(t), 3);
  float f = t - float(i);
  for (int k = 0; k < 3; ++k) rgb[k] = toByte(stops[i][k] * (1 - f) + stops[i + 1][k] * f);
}

}  // namespace

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

void saveDepthPng(const std::string& path, const RenderedImage& img, float nearDepth, float farDepth) {
  ImageRGBA8 out{img.width, img.height, std::vector<uint8_t>(size_t(img.width) * img.height * 4, 255)};
  const float span = std::max(farDepth - nearDepth, 1e-6f);
  for (size_t p = 0; p < size_t(img.width) * img.height; ++p) {
    if (img.opacity[p] < 0.5f) {
      out.rgba[p * 4] = out.rgba[p * 4 + 1] = out.rgba[p * 4 + 2] = 0;
      continue;
    }
    colormap((img.depth[p] - nearDepth) / span, &out.rgba[p * 4]);
  }
  savePng(path, out);
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

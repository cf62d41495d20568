#include "lib/pixel_text.h"

#include <algorithm>
#include <cmath>
#include <vector>

// stb_easy_font is a header of static functions, some of which this file does not call.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

namespace vknerf::nerf {

uint32_t textWidth(const std::string& text) {
  std::string copy = text;  // stb_easy_font takes a char*
  return uint32_t(stb_easy_font_width(copy.data()));
}

void drawText(ImageRGBA8& image, int x, int y, const std::string& text, std::array<uint8_t, 3> colour) {
  struct Vertex {
    float x, y, z;
    uint8_t rgba[4];
  };
  std::string copy = text;
  std::vector<Vertex> quads(copy.size() * 70 + 4);  // stb's estimate: ~270 bytes (17 vertices) a character
  const int n = stb_easy_font_print(float(x), float(y), copy.data(), nullptr, quads.data(),
                                    int(quads.size() * sizeof(Vertex)));
  // Every quad is an axis-aligned rectangle: vertices 0 and 2 are opposite corners.
  for (int q = 0; q < n; ++q) {
    const Vertex& a = quads[size_t(q) * 4];
    const Vertex& b = quads[size_t(q) * 4 + 2];
    const int x0 = std::max(0, int(std::lround(std::min(a.x, b.x)))), x1 = std::min(int(image.width), int(std::lround(std::max(a.x, b.x))));
    const int y0 = std::max(0, int(std::lround(std::min(a.y, b.y)))), y1 = std::min(int(image.height), int(std::lround(std::max(a.y, b.y))));
    for (int py = y0; py < y1; ++py)
      for (int px = x0; px < x1; ++px) {
        uint8_t* p = &image.rgba[(size_t(py) * image.width + size_t(px)) * 4];
        p[0] = colour[0], p[1] = colour[1], p[2] = colour[2], p[3] = 255;
      }
  }
}

}  // namespace vknerf::nerf

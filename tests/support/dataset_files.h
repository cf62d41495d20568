#pragma once
// Files for the dataset tests: tiny generated images, transforms and COLMAP text, camera poses as
// the files carry them.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "io/image_io.h"
#include "support/temp_dir.h"
#include "vknerf/dataset.h"

namespace vknerf::test {

namespace fs = std::filesystem;
using nlohmann::json;

inline void writeText(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << text;
}

inline void writeJson(const fs::path& p, const json& j) { writeText(p, j.dump(2)); }

// A deterministic, non-uniform RGBA image; `transparent` makes its left third fully transparent.
inline ImageRGBA8 patternImage(uint32_t w, uint32_t h, uint32_t seed, bool transparent = false) {
  ImageRGBA8 img{w, h, std::vector<uint8_t>(size_t(w) * h * 4)};
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      uint8_t* p = &img.rgba[(size_t(y) * w + x) * 4];
      p[0] = uint8_t((x * 37 + y * 11 + seed * 53) % 256);
      p[1] = uint8_t((x * 7 + y * 29 + seed * 17) % 256);
      p[2] = uint8_t((x * 3 + y * 5 + seed * 101) % 256);
      p[3] = transparent && x < w / 3 ? 0 : 255;
    }
  return img;
}

inline void writePng(const fs::path& p, const ImageRGBA8& img) {
  fs::create_directories(p.parent_path());
  nerf::savePng(p.string(), img);
}

// Camera-to-world (OpenGL convention, row-major 4x4) of a camera at `eye` looking at `target`.
inline std::array<double, 16> lookAt(std::array<double, 3> eye, std::array<double, 3> target) {
  auto norm = [](std::array<double, 3> v) {
    double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return std::array<double, 3>{v[0] / n, v[1] / n, v[2] / n};
  };
  auto cross = [](std::array<double, 3> a, std::array<double, 3> b) {
    return std::array<double, 3>{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  auto back = norm({eye[0] - target[0], eye[1] - target[1], eye[2] - target[2]});
  std::array<double, 3> up = std::fabs(back[2]) > 0.99 ? std::array<double, 3>{0, 1, 0} : std::array<double, 3>{0, 0, 1};
  auto right = norm(cross(up, back));
  auto camUp = cross(back, right);
  return {right[0], camUp[0], back[0], eye[0], right[1], camUp[1], back[1], eye[1],
          right[2], camUp[2], back[2], eye[2], 0, 0, 0, 1};
}

inline json matrixJson(const std::array<double, 16>& m) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m[4 * r], m[4 * r + 1], m[4 * r + 2], m[4 * r + 3]});
  return rows;
}

}  // namespace vknerf::test

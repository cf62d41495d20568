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

#include "vknerf/image_io.h"
#include "support/temp_dir.h"
#include "vknerf/camera.h"
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
  vknerf::savePng(p.string(), img);
}

// Camera-to-world (vknerf::lookAt) of a camera at `eye` looking at `target`, +Z up, or +Y when it
// looks (nearly) straight up or down; in doubles, as the dataset files carry poses.
inline std::array<double, 16> poseLookingAt(std::array<double, 3> eye, std::array<double, 3> target) {
  const double back[3] = {eye[0] - target[0], eye[1] - target[1], eye[2] - target[2]};
  const double vertical = std::fabs(back[2]) / std::sqrt(back[0] * back[0] + back[1] * back[1] + back[2] * back[2]);
  const std::array<float, 3> up = vertical > 0.99 ? std::array<float, 3>{0, 1, 0} : std::array<float, 3>{0, 0, 1};
  const auto m = lookAt({float(eye[0]), float(eye[1]), float(eye[2])},
                        {float(target[0]), float(target[1]), float(target[2])}, up);
  std::array<double, 16> out;
  for (int k = 0; k < 16; ++k) out[k] = m[k];
  return out;
}

inline json matrixJson(const std::array<double, 16>& m) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m[4 * r], m[4 * r + 1], m[4 * r + 2], m[4 * r + 3]});
  return rows;
}

}  // namespace vknerf::test

#pragma once
// A posed pinhole camera in the nerf_synthetic / OpenGL convention: camera-to-world matrix,
// camera looking down -Z with +Y up and +X right; pixel (x, y) counts rows downwards.
#include <array>
#include <cstdint>

namespace vknerf {

struct Camera {
  float fx = 0, fy = 0, cx = 0, cy = 0;  // focal lengths and principal point, pixels
  uint32_t width = 0, height = 0;
  std::array<float, 16> c2w{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // row-major 4x4
};

struct Aabb {
  std::array<float, 3> min{-1, -1, -1};
  std::array<float, 3> max{1, 1, 1};
};

}  // namespace vknerf

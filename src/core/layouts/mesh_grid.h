#pragma once
// The sample grid a mesh is extracted from, and the welded, indexed triangle mesh extraction
// returns: marching cubes on the device (src/nerf/mesh/marching_cubes.h), the model's mesh export
// and the CPU reference (tests/reference/mesh/marching_cubes.h) share them.
#include <array>
#include <cstdint>
#include <vector>

namespace vknerf::core {

// n[0] x n[1] x n[2] samples, x fastest; sample (i, j, k) lies at origin + (i, j, k) * spacing.
struct GridLayout {
  std::array<uint32_t, 3> n{0, 0, 0};
  std::array<float, 3> origin{0, 0, 0}, spacing{1, 1, 1};
  uint64_t points() const { return uint64_t(n[0]) * n[1] * n[2]; }
  // Cells between samples: (n - 1) per axis (0 when an axis has fewer than 2 samples).
  uint64_t cells() const;
};

struct TriangleMesh {
  std::vector<float> positions;     // xyz per vertex
  std::vector<uint32_t> triangles;  // 3 vertex ids per triangle, counter-clockwise seen from outside
};

}  // namespace vknerf::core

#pragma once
// CPU reference for marching cubes (shaders/mesh/mc_*.comp): the case table both use, and the
// extraction of a welded, indexed triangle mesh from a density grid. Vertices are numbered in the
// order of the grid edges they lie on, triangles in the order of their cells and of the table, so
// the device's output (edge flags and cell counts scanned in the same orders) is identical in its
// indices and equal in its positions up to float rounding.
#include <array>
#include <cstdint>
#include <vector>

namespace vknerf::ref {

// n[0] x n[1] x n[2] samples, x fastest; sample (i, j, k) lies at origin + (i, j, k) * spacing.
struct GridLayout {
  std::array<uint32_t, 3> n{0, 0, 0};
  std::array<float, 3> origin{0, 0, 0}, spacing{1, 1, 1};
  uint64_t points() const { return uint64_t(n[0]) * n[1] * n[2]; }
  // Cells between samples: (n - 1) per axis (0 when an axis has fewer than 2 samples).
  uint64_t cells() const;
};

// A density per sample of the layout.
struct DensityGrid : GridLayout {
  std::vector<float> values;
};

struct TriangleMesh {
  std::vector<float> positions;     // xyz per vertex
  std::vector<uint32_t> triangles;  // 3 vertex ids per triangle, counter-clockwise seen from outside
};

// A sample is inside the surface when its density is >= threshold (NaN is outside).
inline bool insideSurface(float density, float threshold) { return density >= threshold; }

// ---- Cube layout: corner c at (c & 1, (c >> 1) & 1, (c >> 2) & 1) from the cell's lowest sample. ----
// Cube edge e runs along axis e / 4 from corner kCubeEdgeCorner[e]; grid edge 3 * sample + axis
// runs from that sample along that axis (the last sample along an axis owns no edge that way).
inline constexpr uint32_t kCubeEdgeCorner[12] = {0, 2, 4, 6, 0, 1, 4, 5, 0, 1, 2, 3};

// Per configuration (bit c set: corner c inside) kMcTableStride uints: the triangle count, then 3
// cube edges per triangle. Built from first principles (mc_table.cpp): on each cube face the
// crossings are joined so that every inside corner is cut off alone, which two cells sharing the
// face agree on, so the mesh is closed; the joined segments form loops, fanned into triangles.
inline constexpr uint32_t kMcMaxTriangles = 5;
inline constexpr uint32_t kMcTableStride = 16;
const std::vector<uint32_t>& marchingCubesTable();

// Where grid edge `edge` crosses the threshold: linear interpolation between its two samples, the
// formula and order of operations of shaders/mesh/mc_write_vertices.comp.
std::array<float, 3> edgeVertex(const DensityGrid& grid, uint64_t edge, float threshold);

TriangleMesh marchingCubes(const DensityGrid& grid, float threshold);

}  // namespace vknerf::ref

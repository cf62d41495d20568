#pragma once
// CPU reference for marching cubes (shaders/mesh/mc_*.comp): the extraction of a welded, indexed
// triangle mesh from a density grid. The case table both use, the grid's layout and the mesh are
// production's (src/core/layouts/marching_cubes_table.h, src/core/layouts/mesh_grid.h). Vertices
// are numbered in the order of the grid edges they lie on, triangles in the order of their cells and
// of the table, so the device's output (edge flags and cell counts scanned in the same orders) is
// identical in its indices and equal in its positions up to float rounding.
#include <array>
#include <cstdint>
#include <vector>

#include "core/layouts/marching_cubes_table.h"
#include "core/layouts/mesh_grid.h"

namespace vknerf::ref {

using core::GridLayout;
using core::kCubeEdgeCorner;
using core::kMcMaxTriangles;
using core::kMcTableStride;
using core::marchingCubesTable;
using core::TriangleMesh;

// A density per sample of the layout.
struct DensityGrid : GridLayout {
  std::vector<float> values;
};

// A sample is inside the surface when its density is >= threshold (NaN is outside).
inline bool insideSurface(float density, float threshold) { return density >= threshold; }

// Where grid edge `edge` crosses the threshold: linear interpolation between its two samples, the
// formula and order of operations of shaders/mesh/mc_write_vertices.comp.
std::array<float, 3> edgeVertex(const DensityGrid& grid, uint64_t edge, float threshold);

TriangleMesh marchingCubes(const DensityGrid& grid, float threshold);

}  // namespace vknerf::ref

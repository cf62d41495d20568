#pragma once
// The marching-cubes case table and the cube layout it is written in, which the device's kernels
// (shaders/mesh/marching_cubes.glsl, the table as a storage buffer) and the CPU reference
// (tests/reference/mesh/marching_cubes.h) both use.
#include <cstdint>
#include <vector>

namespace vknerf::core {

// ---- Cube layout: corner c at (c & 1, (c >> 1) & 1, (c >> 2) & 1) from the cell's lowest sample. ----
// Cube edge e runs along axis e / 4 from corner kCubeEdgeCorner[e]; grid edge 3 * sample + axis
// runs from that sample along that axis (the last sample along an axis owns no edge that way).
inline constexpr uint32_t kCubeEdgeCorner[12] = {0, 2, 4, 6, 0, 1, 4, 5, 0, 1, 2, 3};

// Per configuration (bit c set: corner c inside) kMcTableStride uints: the triangle count, then 3
// cube edges per triangle. Built from first principles (marching_cubes_table.cpp): on each cube face the
// crossings are joined so that every inside corner is cut off alone, which two cells sharing the
// face agree on, so the mesh is closed; the joined segments form loops, fanned into triangles.
inline constexpr uint32_t kMcMaxTriangles = 5;
inline constexpr uint32_t kMcTableStride = 16;
const std::vector<uint32_t>& marchingCubesTable();

}  // namespace vknerf::core

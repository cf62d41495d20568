// The marching-cubes case table, derived rather than transcribed: for each of the 256 inside/outside
// configurations, the crossings on each face are joined into oriented segments, the segments into
// loops around the cube, the loops fanned into triangles.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "core/layouts/marching_cubes_table.h"

namespace vknerf::core {
namespace {

uint32_t cubeEdge(uint32_t a, uint32_t b) {
  const uint32_t lo = a < b ? a : b, axisBit = a ^ b;  // neighbours differ in one bit: the axis
  const uint32_t axis = axisBit == 1 ? 0 : axisBit == 2 ? 1 : 2;
  for (uint32_t e = axis * 4; e < axis * 4 + 4; ++e)
    if (kCubeEdgeCorner[e] == lo) return e;
  throw std::logic_error("marching cubes: corners are not neighbours");
}

// Whether cube edges a and b lie on one face of the cube.
bool shareFace(uint32_t a, uint32_t b) {
  const uint32_t ca = kCubeEdgeCorner[a], cb = kCubeEdgeCorner[b];
  // A face fixes one coordinate bit: both edges keep it at the same value along their length.
  for (uint32_t axis = 0; axis < 3; ++axis) {
    if (axis == a / 4 || axis == b / 4) continue;
    if (((ca >> axis) & 1u) == ((cb >> axis) & 1u)) return true;
  }
  return false;
}

// The four corners of face (axis, side), counter-clockwise seen from outside the cube.
std::array<uint32_t, 4> faceCorners(uint32_t axis, uint32_t side) {
  const uint32_t u = (axis + 1) % 3, v = (axis + 2) % 3;
  const uint32_t uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::array<uint32_t, 4> q{};
  for (int i = 0; i < 4; ++i) q[i] = (side << axis) | (uv[i][0] << u) | (uv[i][1] << v);
  // u x v = +axis: counter-clockwise seen from the + side; the - side sees it reversed.
  if (side == 0) std::swap(q[1], q[3]);
  return q;
}

std::vector<uint32_t> buildTable() {
  std::vector<uint32_t> table(256 * kMcTableStride, 0);
  for (uint32_t config = 0; config < 256; ++config) {
    auto inside = [&](uint32_t c) { return (config >> c) & 1u; };
    // next[e]: the crossing that the segment starting at crossing e ends at. A segment starts where
    // a face's counter-clockwise walk enters the inside and ends where it next leaves it, so each
    // inside corner of a face with four crossings is cut off by its own segment.
    int next[12];
    for (int& n : next) n = -1;
    for (uint32_t axis = 0; axis < 3; ++axis)
      for (uint32_t side = 0; side < 2; ++side) {
        const auto q = faceCorners(axis, side);
        for (uint32_t i = 0; i < 4; ++i) {
          if (inside(q[i]) || !inside(q[(i + 1) % 4])) continue;
          uint32_t j = i + 1;
          while (inside(q[j % 4])) ++j;
          next[cubeEdge(q[i], q[(i + 1) % 4])] = int(cubeEdge(q[(j - 1) % 4], q[j % 4]));
        }
      }
    // Every crossed edge lies on two faces, walked in opposite directions, so it starts exactly one
    // segment and ends exactly one: the segments form disjoint loops.
    uint32_t* entry = &table[config * kMcTableStride];
    bool visited[12] = {};
    uint32_t triangles = 0;
    for (uint32_t e = 0; e < 12; ++e) {
      if (next[e] < 0 || visited[e]) continue;
      std::vector<uint32_t> loop;
      for (int k = int(e); !visited[k]; k = next[k]) {
        visited[k] = true;
        loop.push_back(uint32_t(k));
      }
      // The loop runs counter-clockwise seen from the outside (the side of lower density): its
      // fan faces out. The fan starts where it draws fewest diagonals across a cube face: the cell
      // beyond that face could draw the same one, and the surfaces would touch along it.
      size_t apex = 0, fewest = SIZE_MAX;
      for (size_t a = 0; a < loop.size(); ++a) {
        size_t across = 0;
        for (size_t k = 2; k + 1 < loop.size(); ++k) across += shareFace(loop[a], loop[(a + k) % loop.size()]);
        if (across < fewest) fewest = across, apex = a;
      }
      std::rotate(loop.begin(), loop.begin() + ptrdiff_t(apex), loop.end());
      for (size_t k = 1; k + 1 < loop.size(); ++k) {
        if (triangles == kMcMaxTriangles) throw std::logic_error("marching cubes: a case needs more triangles than the table holds");
        uint32_t* t = entry + 1 + 3 * triangles++;
        t[0] = loop[0], t[1] = loop[k], t[2] = loop[k + 1];
      }
    }
    entry[0] = triangles;
  }
  return table;
}

}  // namespace

const std::vector<uint32_t>& marchingCubesTable() {
  static const std::vector<uint32_t> table = buildTable();
  return table;
}

}  // namespace vknerf::core

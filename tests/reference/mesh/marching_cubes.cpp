#include "reference/mesh/marching_cubes.h"

namespace vknerf::ref {

std::array<float, 3> edgeVertex(const DensityGrid& g, uint64_t edge, float threshold) {
  const uint64_t sample = edge / 3;
  const uint32_t axis = uint32_t(edge % 3);
  const uint64_t idx[3] = {sample % g.n[0], (sample / g.n[0]) % g.n[1], sample / (uint64_t(g.n[0]) * g.n[1])};
  const uint64_t stride[3] = {1, g.n[0], uint64_t(g.n[0]) * g.n[1]};
  const float a = g.values[sample], b = g.values[sample + stride[axis]];
  float t = (threshold - a) / (b - a);
  if (!(t >= 0.0f && t <= 1.0f)) t = 0.5f;  // a NaN or infinite sample: the edge's middle
  std::array<float, 3> p{};
  for (uint32_t k = 0; k < 3; ++k) p[k] = g.origin[k] + g.spacing[k] * (float(idx[k]) + (k == axis ? t : 0.0f));
  return p;
}

TriangleMesh marchingCubes(const DensityGrid& g, float threshold) {
  TriangleMesh mesh;
  if (g.cells() == 0) return mesh;
  const uint64_t points = g.points();
  const uint64_t stride[3] = {1, g.n[0], uint64_t(g.n[0]) * g.n[1]};
  auto in = [&](uint64_t s) { return insideSurface(g.values[s], threshold); };
  // Welding: one vertex per crossed grid edge, numbered in edge order.
  std::vector<uint32_t> vertexOf(points * 3, UINT32_MAX);
  uint32_t vertices = 0;
  for (uint64_t s = 0; s < points; ++s) {
    const uint64_t idx[3] = {s % g.n[0], (s / g.n[0]) % g.n[1], s / stride[2]};
    for (uint32_t axis = 0; axis < 3; ++axis) {
      if (idx[axis] + 1 >= g.n[axis] || in(s) == in(s + stride[axis])) continue;
      vertexOf[s * 3 + axis] = vertices++;
      const auto p = edgeVertex(g, s * 3 + axis, threshold);
      mesh.positions.insert(mesh.positions.end(), p.begin(), p.end());
    }
  }
  const auto& table = marchingCubesTable();
  const uint32_t cx = g.n[0] - 1, cy = g.n[1] - 1, cz = g.n[2] - 1;
  for (uint32_t z = 0; z < cz; ++z)
    for (uint32_t y = 0; y < cy; ++y)
      for (uint32_t x = 0; x < cx; ++x) {
        const uint64_t base = x + stride[1] * y + stride[2] * z;
        auto corner = [&](uint32_t c) { return base + (c & 1) * stride[0] + ((c >> 1) & 1) * stride[1] + ((c >> 2) & 1) * stride[2]; };
        uint32_t config = 0;
        for (uint32_t c = 0; c < 8; ++c) config |= uint32_t(in(corner(c))) << c;
        const uint32_t* entry = &table[config * kMcTableStride];
        for (uint32_t i = 0; i < entry[0] * 3; ++i) {
          const uint32_t e = entry[1 + i];
          mesh.triangles.push_back(vertexOf[corner(kCubeEdgeCorner[e]) * 3 + e / 4]);
        }
      }
  return mesh;
}

}  // namespace vknerf::ref

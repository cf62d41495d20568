#pragma once
// Properties of a triangle mesh the marching-cubes tests check: closed (every edge shared by
// exactly two triangles, once in each direction: consistently oriented), its signed volume, and
// the analytic fields the tests sample.
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "reference/mesh/marching_cubes.h"

namespace vknerf::test {

// "" when every directed edge (a, b) of a triangle appears once and its reverse (b, a) once in
// another triangle: the surface is closed and its triangles agree on one side; else what breaks.
inline std::string closedAndOriented(const std::vector<uint32_t>& triangles) {
  std::map<std::pair<uint32_t, uint32_t>, int> directed;
  for (size_t t = 0; t + 2 < triangles.size(); t += 3)
    for (int k = 0; k < 3; ++k) ++directed[{triangles[t + k], triangles[t + (k + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    if (count != 1) return "edge " + std::to_string(edge.first) + "-" + std::to_string(edge.second) + " is used " +
                           std::to_string(count) + " times in one direction";
    if (!directed.count({edge.second, edge.first}))
      return "edge " + std::to_string(edge.first) + "-" + std::to_string(edge.second) + " has no neighbour";
  }
  return "";
}

// Sum of the tetrahedra (origin, a, b, c): the enclosed volume, positive when the triangles are
// counter-clockwise seen from outside (outward normals).
inline double signedVolume(const std::vector<float>& p, const std::vector<uint32_t>& triangles) {
  double v = 0;
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const float* a = &p[3 * triangles[t]];
    const float* b = &p[3 * triangles[t + 1]];
    const float* c = &p[3 * triangles[t + 2]];
    v += (double(a[0]) * (double(b[1]) * c[2] - double(b[2]) * c[1]) - double(a[1]) * (double(b[0]) * c[2] - double(b[2]) * c[0]) +
          double(a[2]) * (double(b[0]) * c[1] - double(b[1]) * c[0])) / 6.0;
  }
  return v;
}

// An n^3 grid over [-1, 1]^3 sampling f(x, y, z).
template <class F>
ref::DensityGrid sampledGrid(uint32_t n, F f) {
  ref::DensityGrid g;
  g.n = {n, n, n};
  const float h = 2.0f / float(n - 1);
  g.origin = {-1, -1, -1};
  g.spacing = {h, h, h};
  g.values.resize(g.points());
  for (uint32_t z = 0; z < n; ++z)
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x)
        g.values[x + n * (y + size_t(n) * z)] = f(-1.0 + h * x, -1.0 + h * y, -1.0 + h * z);
  return g;
}

// Densities that fall through `threshold` 1 at the surface: a ball of radius r (density 2 - |x| / r)
// and an axis-aligned box of half sizes h (2 - max_k |x_k| / h_k).
inline float ballDensity(double x, double y, double z, double r) { return float(2.0 - std::sqrt(x * x + y * y + z * z) / r); }
inline float boxDensity(double x, double y, double z, const std::array<double, 3>& h) {
  return float(2.0 - std::max({std::fabs(x) / h[0], std::fabs(y) / h[1], std::fabs(z) / h[2]}));
}

}  // namespace vknerf::test

#pragma once
// CPU reference for the multiresolution hash encoding (Müller et al. 2022): shaders/encoding/encode_hash.comp
// (forward) and shaders/encoding/encode_hash_backward.comp (dL/dtable), in float or double. The
// levels' resolutions and the table's parameter layout are production's
// (src/core/layouts/hash_grid_layout.h).
//
// A position p in [-1, 1]^3 maps to u = (p + 1) / 2 in [0, 1]^3 (clamped), then x = u * res_l; the
// cell is i = min(floor(x), res_l - 1) (so u = 1 lands in the last cell with weight 1) and the
// feature is the trilinear blend of the 8 corner vertices' table entries.
// Vertex v = (vx, vy, vz) has table index
//   dense  (res_l + 1)^3 <= 2^T:  vx + (res_l + 1) * (vy + (res_l + 1) * vz)
//   hashed otherwise:             (vx * 1 ^ vy * 2654435761 ^ vz * 805459861) mod 2^T  (uint32 wrap)
// Output: L * F features per sample, level-major: feature[l * F + f].
// With contraction S > 0 the lookup's p is hashGridContract(p, S) below.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/layouts/hash_grid_layout.h"
#include "reference/rng.h"

namespace vknerf::ref {

using core::HashGridConfig;
using core::hashGridDense;
using core::hashGridInitialParameters;
using core::hashGridParameterCount;
using core::hashGridResolution;
using core::hashGridUsedRuns;
using core::TableRun;

inline uint32_t hashGridIndex(uint32_t res, bool dense, uint32_t log2Table, uint32_t vx, uint32_t vy, uint32_t vz) {
  if (dense) return vx + (res + 1) * (vy + (res + 1) * vz);
  return (vx * 1u ^ vy * 2654435761u ^ vz * 805459861u) & ((1u << log2Table) - 1u);
}

// mip-NeRF 360's contraction with the max norm (nerfacto's SceneContraction(order=inf)) about the
// inner cube [-1/S, 1/S]^3 of the box: q = S p; q if m = max_k |q_k| <= 1, else (2 - 1/m) q / m; then
// halved, so the box's contraction lies in [-1, 1]^3 with the inner cube over its middle half.
template <class T>
std::array<T, 3> hashGridContract(const T* p, uint32_t scale) {
  if (scale == 0) return {p[0], p[1], p[2]};
  T q[3], m = T(0);
  for (int k = 0; k < 3; ++k) q[k] = p[k] * T(scale), m = std::max(m, std::abs(q[k]));
  const T f = m <= T(1) ? T(1) : (T(2) - T(1) / m) / m;
  return {T(0.5) * (f * q[0]), T(0.5) * (f * q[1]), T(0.5) * (f * q[2])};
}

template <class T> struct HashCorner {
  uint32_t entry;  // index into the flat table, in entries: l * 2^T + index (multiply by F for floats)
  T weight;
};

// The 8 corners of p's cell at `level`, corner c = (bit0: +x, bit1: +y, bit2: +z). The arithmetic is
// the shader's, step for step, so the float instantiation reproduces it.
template <class T>
std::array<HashCorner<T>, 8> hashGridCorners(const HashGridConfig& c, uint32_t level, const T* box) {
  const std::array<T, 3> p = hashGridContract(box, c.contraction);
  const uint32_t res = hashGridResolution(c, level);
  const bool dense = hashGridDense(c, level);
  uint32_t cell[3];
  T w[3];
  for (int k = 0; k < 3; ++k) {
    T u = std::clamp((p[k] + T(1)) * T(0.5), T(0), T(1));
    T x = u * T(res);
    cell[k] = std::min(uint32_t(std::floor(x)), res - 1);
    w[k] = x - T(cell[k]);
  }
  std::array<HashCorner<T>, 8> out;
  const uint32_t base = level << c.log2TableSize;
  for (uint32_t k = 0; k < 8; ++k) {
    uint32_t dx = k & 1, dy = (k >> 1) & 1, dz = (k >> 2) & 1;
    T wx = dx ? w[0] : T(1) - w[0], wy = dy ? w[1] : T(1) - w[1], wz = dz ? w[2] : T(1) - w[2];
    out[k] = {base + hashGridIndex(res, dense, c.log2TableSize, cell[0] + dx, cell[1] + dy, cell[2] + dz),
              wx * wy * wz};
  }
  return out;
}

// L * F features of position p (3 components) from `table` (layout above).
template <class T>
std::vector<T> hashEncoding(const HashGridConfig& c, const T* table, const T* p) {
  const uint32_t F = c.featuresPerLevel;
  std::vector<T> out(size_t(c.levels) * F, T(0));
  for (uint32_t l = 0; l < c.levels; ++l) {
    auto corners = hashGridCorners(c, l, p);
    for (const auto& k : corners)
      for (uint32_t f = 0; f < F; ++f) out[l * F + f] += k.weight * table[size_t(k.entry) * F + f];
  }
  return out;
}

// grads += d features / d table applied to dFeatures (L * F values): each corner's entry receives
// weight * dFeatures[l * F + f]. The encoding is linear in the table, so this is its exact gradient.
template <class T>
void hashEncodingBackward(const HashGridConfig& c, const T* p, const T* dFeatures, T* grads) {
  const uint32_t F = c.featuresPerLevel;
  for (uint32_t l = 0; l < c.levels; ++l)
    for (const auto& k : hashGridCorners(c, l, p))
      for (uint32_t f = 0; f < F; ++f) grads[size_t(k.entry) * F + f] += k.weight * dFeatures[l * F + f];
}

}  // namespace vknerf::ref

#pragma once
// CPU reference for the multiresolution hash encoding (Müller et al. 2022): shaders/encoding/encode_hash.comp
// (forward) and shaders/encoding/encode_hash_backward.comp (dL/dtable), in float or double.
//
// Level l has resolution res_l = floor(N_min * b^l) cells per axis, i.e. res_l + 1 grid vertices.
// A position p in [-1, 1]^3 maps to u = (p + 1) / 2 in [0, 1]^3 (clamped), then x = u * res_l; the
// cell is i = min(floor(x), res_l - 1) (so u = 1 lands in the last cell with weight 1) and the
// feature is the trilinear blend of the 8 corner vertices' table entries.
// Vertex v = (vx, vy, vz) has table index
//   dense  (res_l + 1)^3 <= 2^T:  vx + (res_l + 1) * (vy + (res_l + 1) * vz)
//   hashed otherwise:             (vx * 1 ^ vy * 2654435761 ^ vz * 805459861) mod 2^T  (uint32 wrap)
// Parameter layout: one flat float array, level-major, F floats per entry:
//   table[(l * 2^T + index) * F + f],  L * 2^T * F floats in all
// (dense levels use only the first (res_l + 1)^3 entries of their slot; the rest stay untouched).
// Output: L * F features per sample, level-major: feature[l * F + f].
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "reference/rng.h"

namespace vknerf::ref {

struct HashGridConfig {
  uint32_t levels = 16;           // L
  uint32_t featuresPerLevel = 2;  // F: 1, 2, 4 or 8
  uint32_t log2TableSize = 19;    // T: 2^T entries per level
  uint32_t baseResolution = 16;   // N_min
  double growthFactor = 1.5;      // b
};

// floor(N_min * b^l). The relative 1e-12 nudge keeps products that are integers in exact arithmetic
// (b = 2, or 1.5^l * 16 for small l) from flooring one below after pow() rounds down.
inline uint32_t hashGridResolution(const HashGridConfig& c, uint32_t level) {
  return uint32_t(std::floor(double(c.baseResolution) * std::pow(c.growthFactor, double(level)) * (1 + 1e-12)));
}

inline bool hashGridDense(const HashGridConfig& c, uint32_t level) {
  uint64_t n = uint64_t(hashGridResolution(c, level)) + 1;
  return n * n * n <= (uint64_t(1) << c.log2TableSize);
}

inline size_t hashGridParameterCount(const HashGridConfig& c) {
  return size_t(c.levels) * (size_t(1) << c.log2TableSize) * c.featuresPerLevel;
}

// The part of the table a lookup can reach, as runs of floats [first, first + count) in order: a
// dense level's (res_l + 1)^3 entries at the start of its slot, a hashed level's whole slot; runs
// that meet are merged. Nothing outside them is ever read or given a gradient.
struct TableRun {
  size_t first = 0, count = 0;
};
inline std::vector<TableRun> hashGridUsedRuns(const HashGridConfig& c) {
  std::vector<TableRun> runs;
  const size_t slot = size_t(1) << c.log2TableSize;
  for (uint32_t l = 0; l < c.levels; ++l) {
    const uint64_t vertices = uint64_t(hashGridResolution(c, l)) + 1;
    const size_t entries = hashGridDense(c, l) ? size_t(vertices * vertices * vertices) : slot;
    const size_t first = l * slot * c.featuresPerLevel, count = entries * c.featuresPerLevel;
    if (!runs.empty() && runs.back().first + runs.back().count == first)
      runs.back().count += count;
    else
      runs.push_back({first, count});
  }
  return runs;
}

inline uint32_t hashGridIndex(uint32_t res, bool dense, uint32_t log2Table, uint32_t vx, uint32_t vy, uint32_t vz) {
  if (dense) return vx + (res + 1) * (vy + (res + 1) * vz);
  return (vx * 1u ^ vy * 2654435761u ^ vz * 805459861u) & ((1u << log2Table) - 1u);
}

// Deterministic init: uniform(-1e-4, 1e-4) from the counter-based RNG, entry i = rng01(seed, i, 0).
inline std::vector<float> hashGridInitialParameters(const HashGridConfig& c, uint32_t seed) {
  std::vector<float> t(hashGridParameterCount(c));
  for (size_t i = 0; i < t.size(); ++i) t[i] = (2.0f * rng01(seed, uint32_t(i), 0) - 1.0f) * 1e-4f;
  return t;
}

template <class T> struct HashCorner {
  uint32_t entry;  // index into the flat table, in entries: l * 2^T + index (multiply by F for floats)
  T weight;
};

// The 8 corners of p's cell at `level`, corner c = (bit0: +x, bit1: +y, bit2: +z). The arithmetic is
// the shader's, step for step, so the float instantiation reproduces it.
template <class T>
std::array<HashCorner<T>, 8> hashGridCorners(const HashGridConfig& c, uint32_t level, const T* p) {
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

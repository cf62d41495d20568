#pragma once
// The parameter layout of the multiresolution hash encoding (Müller et al. 2022), which the device
// stage (src/nerf/encoding/hash_encoding.h), the optimizer's view of the table and the CPU reference
// (tests/reference/encoding/hash_encoding.h: the lookup itself) share.
//
// Level l has resolution res_l = floor(N_min * b^l) cells per axis, i.e. res_l + 1 grid vertices.
// A level is dense when its (res_l + 1)^3 vertices fit in 2^T entries (each vertex its own entry),
// hashed otherwise.
// Parameter layout: one flat float array, level-major, F floats per entry:
//   table[(l * 2^T + index) * F + f],  L * 2^T * F floats in all
// (dense levels use only the first (res_l + 1)^3 entries of their slot; the rest stay untouched).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/math/rng.h"

namespace vknerf::core {

struct HashGridConfig {
  uint32_t levels = 16;           // L
  uint32_t featuresPerLevel = 2;  // F: 1, 2, 4 or 8
  uint32_t log2TableSize = 19;    // T: 2^T entries per level
  uint32_t baseResolution = 16;   // N_min
  double growthFactor = 1.5;      // b
  // 0: the grid spans the box, [-1, 1]^3. S > 0: it spans the box contracted about its inner cube
  // [-1/S, 1/S]^3 (mip-NeRF 360's contraction with the max norm, tests/reference/encoding/hash_encoding.h),
  // the inner cube over the middle half of every level: for nested cascades, S = 2^(cascades - 1).
  uint32_t contraction = 0;
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

// Deterministic init: uniform(-1e-4, 1e-4) from the counter-based RNG, entry i = rng01(seed, i, 0).
inline std::vector<float> hashGridInitialParameters(const HashGridConfig& c, uint32_t seed) {
  std::vector<float> t(hashGridParameterCount(c));
  for (size_t i = 0; i < t.size(); ++i) t[i] = (2.0f * rng01(seed, uint32_t(i), 0) - 1.0f) * 1e-4f;
  return t;
}

}  // namespace vknerf::core

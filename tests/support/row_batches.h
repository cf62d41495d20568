#pragma once
// Inputs shared by the tests of the per-sample kernels over part of a batch (row limits, row
// gathers): the fast model's network and a deeper one, and unit directions.
#include <cmath>
#include <cstdint>
#include <vector>

#include "nerf/network/mlp.h"
#include "support/random_values.h"

namespace vknerf::test {

// The fast model's shape (one hidden layer, 16 features, trunc-exp density) and a deeper one with
// a skip layer (two-input dense layers).
inline std::vector<nerf::MlpConfig> fastAndDeepNetworks() {
  std::vector<nerf::MlpConfig> c(2);
  c[0].depth = 1, c[0].width = 64, c[0].skipLayer = 0, c[0].posDims = 16, c[0].dirDims = 16, c[0].featureWidth = 16;
  c[0].density = DensityActivation::TruncExp;
  c[1].depth = 3, c[1].width = 32, c[1].skipLayer = 2, c[1].posDims = 21, c[1].dirDims = 9;
  return c;
}

// `rows` random unit directions, a vec4 each (w unused).
inline std::vector<float> unitDirections(uint32_t rows, uint32_t seed) {
  std::vector<float> dirs = uniformFloats(4 * size_t(rows), seed);
  for (uint32_t r = 0; r < rows; ++r) {
    float* d = &dirs[4 * size_t(r)];
    const float n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; ++k) d[k] /= n;
  }
  return dirs;
}

}  // namespace vknerf::test

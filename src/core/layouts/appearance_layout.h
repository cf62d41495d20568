#pragma once
// The appearance embedding's tables (src/nerf/encoding/appearance_embedding.h; CPU reference
// tests/reference/encoding/appearance.h): a learned vector a of `dims` floats per training photo and
// its weights W_a (dims rows of the colour layer's `width`). Tables are row-major: `dims` floats per
// photo, `width` per row of W_a.
#include <cstdint>
#include <vector>

#include "core/math/rng.h"

namespace vknerf::core {

// W_a at the start: uniform in +-bound, entry i drawn from rng01(seed, i, 1) (the network's own
// weights draw stream 0).
inline std::vector<float> appearanceWeights(uint32_t dims, uint32_t width, float bound, uint32_t seed) {
  std::vector<float> w(size_t(dims) * width);
  for (size_t i = 0; i < w.size(); ++i) w[i] = (2.0f * rng01(seed, uint32_t(i), 1) - 1.0f) * bound;
  return w;
}

}  // namespace vknerf::core

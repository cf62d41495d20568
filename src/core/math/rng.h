#pragma once
// CPU twin of shaders/common/rng.glsl: same integer hash, bit for bit. Production draws its seeds and
// initial parameters from it; the oracle (tests/reference/) its random samples.
#include <cstdint>

namespace vknerf::core {

inline uint32_t pcgHash(uint32_t v) {
  uint32_t state = v * 747796405u + 2891336453u;
  uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

inline uint32_t rngUint(uint32_t seed, uint32_t a, uint32_t b) { return pcgHash(pcgHash(pcgHash(seed) + a) + b); }

inline float rng01(uint32_t seed, uint32_t a, uint32_t b) { return float(rngUint(seed, a, b) >> 8) * (1.0f / 16777216.0f); }

}  // namespace vknerf::core

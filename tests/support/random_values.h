#pragma once
// Reproducible test inputs: n floats uniform in [lo, hi) from a Mersenne Twister seeded with `seed`.
#include <cstdint>
#include <random>
#include <vector>

namespace vknerf::test {

inline std::vector<float> uniformFloats(size_t n, uint32_t seed, float lo = -1, float hi = 1) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<float> v(n);
  for (auto& x : v) x = u(gen);
  return v;
}

}  // namespace vknerf::test

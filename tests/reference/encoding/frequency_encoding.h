#pragma once
// CPU reference for shaders/sampling/sample_points.comp and shaders/encoding/encode_frequency.comp, in float or double.
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "core/layouts/frequency_layout.h"
#include "vknerf/camera.h"

namespace vknerf::ref {

// Sample position o + t d mapped affinely from the scene box onto [-1, 1]^3.
template <class T>
std::array<T, 3> samplePosition(const std::array<T, 3>& o, const std::array<T, 3>& d, T t, const Aabb& box) {
  std::array<T, 3> p;
  for (int k = 0; k < 3; ++k) {
    T x = o[k] + t * d[k];
    p[k] = T(2) * (x - T(box.min[k])) / (T(box.max[k]) - T(box.min[k])) - T(1);
  }
  return p;
}

// sin(pi x) and cos(pi x) after an exact reduction of x to [-1, 1]: x - 2 round(x / 2) is exact in
// binary floating point (the result is a multiple of ulp(x) no larger than 1), so the large
// frequency bands keep full precision instead of inheriting the rounding of 2^k pi x.
template <class T> T reducePeriod2(T x) { return x - T(2) * std::round(x / T(2)); }
template <class T> T sinPi(T x) { return std::sin(std::numbers::pi_v<T> * reducePeriod2(x)); }
template <class T> T cosPi(T x) { return std::cos(std::numbers::pi_v<T> * reducePeriod2(x)); }

// Number of features gamma produces for `dims` input components: production's
// (src/core/layouts/frequency_layout.h).
using core::frequencyEncodingDims;

// gamma(p) in the column order of the released NeRF code and the seed's pos_enc (§6.3):
//   [p_0 .. p_{D-1}]                                  if includeInput
//   for k in 0..L-1: [sin(2^k pi p_0) .. sin(2^k pi p_{D-1}), cos(2^k pi p_0) .. cos(2^k pi p_{D-1})]
// For a scalar (D = 1) and L = 2 this is (sin pi p, cos pi p, sin 2 pi p, cos 2 pi p).
template <class T>
std::vector<T> frequencyEncoding(const T* p, uint32_t dims, uint32_t levels, bool includeInput) {
  std::vector<T> out;
  out.reserve(frequencyEncodingDims(dims, levels, includeInput));
  if (includeInput)
    for (uint32_t i = 0; i < dims; ++i) out.push_back(p[i]);
  for (uint32_t k = 0; k < levels; ++k) {
    T scale = std::ldexp(T(1), int(k));
    for (uint32_t i = 0; i < dims; ++i) out.push_back(sinPi(scale * p[i]));
    for (uint32_t i = 0; i < dims; ++i) out.push_back(cosPi(scale * p[i]));
  }
  return out;
}

}  // namespace vknerf::ref

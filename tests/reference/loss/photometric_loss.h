#pragma once
// CPU reference for shaders/loss/random_background.comp and shaders/loss/loss_photometric.comp, in float or double.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "core/math/psnr.h"
#include "reference/rng.h"

namespace vknerf::ref {

// Random background colour of ray `ray` for RNG seed `seed` (channels use streams 100, 101, 102 so
// they never coincide with the streams rays.comp draws camera and pixel from).
inline std::array<float, 3> randomBackground(uint32_t seed, uint32_t ray) {
  return {rng01(seed, ray, 100), rng01(seed, ray, 101), rng01(seed, ray, 102)};
}

// Training pixel (packed RGBA8, R in the low byte) alpha-blended over the background colour.
template <class T>
std::array<T, 3> blendTarget(uint32_t rgba8, const std::array<T, 3>& background) {
  T a = T((rgba8 >> 24) & 0xffu) / T(255);
  std::array<T, 3> out;
  for (int c = 0; c < 3; ++c) {
    T v = T((rgba8 >> (8 * c)) & 0xffu) / T(255);
    out[c] = v * a + background[c] * (T(1) - a);
  }
  return out;
}

// Mean squared error over rays and the 3 colour channels, L = sum (pred - target)^2 / (3 R).
// `pred` is (r, g, b, opacity) per ray; opacity takes no part. When `grad` is given it receives
// gradScale * dL/dpred (opacity component 0).
template <class T>
T photometricLoss(std::span<const std::array<T, 4>> pred, std::span<const std::array<T, 3>> target, T gradScale = T(1),
                  std::vector<std::array<T, 4>>* grad = nullptr) {
  const size_t n = pred.size();
  if (grad) grad->assign(n, {T(0), T(0), T(0), T(0)});
  if (n == 0) return T(0);
  const T norm = T(1) / (T(3) * T(n));
  T sum = 0;
  for (size_t r = 0; r < n; ++r) {
    for (int c = 0; c < 3; ++c) {
      T e = pred[r][c] - target[r][c];
      sum += e * e;
      if (grad) (*grad)[r][c] = gradScale * T(2) * e * norm;
    }
  }
  return sum * norm;
}

// PSNR of a mean squared error: production's (src/core/math/psnr.h).
using core::psnrFromMse;

}  // namespace vknerf::ref

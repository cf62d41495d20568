#pragma once
// CPU twin of shaders/selfcheck/field_analytic.glsl.
#include <algorithm>
#include <array>
#include <cmath>

namespace vknerf::ref {

template <class T> std::array<T, 4> analyticField(const std::array<T, 3>& p) {
  auto clamp01 = [](T v) { return std::clamp(v, T(0), T(1)); };
  T dx = p[0] - T(0.1), r = std::sqrt(dx * dx + p[1] * p[1] + p[2] * p[2]);
  T sphere = T(40) * clamp01((T(0.5) - r) / T(0.05));
  T qx = std::abs(p[0] + T(0.45)), qy = std::abs(p[1] - T(0.3)), qz = std::abs(p[2] - T(0.2));
  T fog = T(3) * clamp01((T(0.3) - std::max(qx, std::max(qy, qz))) / T(0.05));
  if (sphere > T(0)) return {T(0.5) + T(0.5) * p[0], T(0.5) + T(0.5) * p[1], T(0.5) + T(0.5) * p[2], sphere + fog};
  return {T(0.9), T(0.4), T(0.1), sphere + fog};
}

}  // namespace vknerf::ref

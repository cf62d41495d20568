#pragma once
// CPU reference for the distortion loss that shaders/render/composite_backward.comp adds to the
// photometric loss (mip-NeRF 360's, eq. 15): per ray
//   L = sum_{i,j} w_i w_j |m_i - m_j| + 1/3 sum_i w_i^2 l_i,
// m_i and l_i the midpoint and length of sample i's interval [t_i, t_i + delta_i] in the ray's
// normalised distance s in [0, 1]. It is small when the weight sits in one short interval and large
// when it is spread along the ray as fog or floaters.
//
// s is mip-NeRF 360's: the distance mapped through the function the samples are spaced by, then
// normalised between the ray's near and far, s(t) = (g(t) - g(near)) / (g(far) - g(near)). Here the
// samples are spaced by the march, step(t) = clamp(t coneAngle, dtMin, dtMax) (one grid: the
// constant dtMin), so g(t) = integral_0^t du / step(u) counts march steps: s is even in steps, the
// same whatever the scene's units (every length scales together) and however near the camera the
// ray starts. The first definition (s = ln t, clamped at t = 1e-3) was neither: its size followed the
// scene's units and the distance to the first sample, and it cost a real hand-held capture 8 dB.
#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

namespace vknerf::ref {

// The march's step as a function of the distance t along the ray: clamp(t coneAngle, dtMin, dtMax);
// coneAngle 0 (one occupancy grid) marches the constant dtMin.
template <class T> struct MarchSpacing {
  T coneAngle = 0, dtMin = 1, dtMax = 1;
};

// g(t) = integral_0^t du / step(u), in closed form over step's three pieces: t / dtMin up to
// t1 = dtMin / coneAngle, then logarithmic up to t2 = dtMax / coneAngle, then linear in dtMax.
template <class T> T marchCoordinate(T t, const MarchSpacing<T>& m) {
  t = std::max(t, T(0));
  if (!(m.coneAngle > 0)) return t / m.dtMin;
  const T t1 = m.dtMin / m.coneAngle, t2 = std::max(m.dtMax, m.dtMin) / m.coneAngle;
  if (t <= t1) return t / m.dtMin;
  if (t <= t2) return T(1) / m.coneAngle + std::log(t / t1) / m.coneAngle;
  return T(1) / m.coneAngle + std::log(t2 / t1) / m.coneAngle + (t - t2) / std::max(m.dtMax, m.dtMin);
}

// One ray's normalised distance: its march spacing and its [near, far] (the box's entry, past the
// near plane, and its exit). With farField, the weight the ray leaves to what lies behind the box
// (T_final = 1 - sum_i w_i, the learned far field's) counts as one more interval, at s = 1 and of
// length 0: mip-NeRF 360's loss sees all of a ray's weight (its scene has no far field), and without
// it a ray lowers its loss by handing weight to the far field (a half-transparent table).
template <class T> struct DistortionRay {
  MarchSpacing<T> spacing;
  T tNear = 0, tFar = 1;
  bool farField = false;

  T s(T t) const {
    const T g0 = marchCoordinate(tNear, spacing);
    // A ray of no length has no samples; the floor only keeps the division finite.
    const T span = std::max(marchCoordinate(tFar, spacing) - g0, T(1e-30));
    return (marchCoordinate(t, spacing) - g0) / span;
  }
  T midpoint(T t, T delta) const { return s(t + delta / 2); }
  T length(T t, T delta) const { return s(t + delta) - s(t); }
};

// The far field's weight T_final = 1 - sum_i w_i (0 when the ray keeps none for it).
template <class T> T farWeightOf(std::span<const T> weights) {
  T sum = 0;
  for (T w : weights) sum += w;
  return std::max(T(1) - sum, T(0));
}

// The definition, O(n^2): the reference the kernel's O(n) prefix sums are tested against. With
// ray.farField, the far field's interval at s = 1 adds 2 T_final sum_i w_i |m_i - 1| (m_i <= 1).
template <class T>
T distortionLoss(std::span<const T> samples, std::span<const T> weights, const DistortionRay<T>& ray) {
  const size_t n = samples.size() / 2;
  T loss = 0;
  for (size_t i = 0; i < n; ++i) {
    const T mi = ray.midpoint(samples[2 * i], samples[2 * i + 1]);
    for (size_t j = 0; j < n; ++j) loss += weights[i] * weights[j] * std::abs(mi - ray.midpoint(samples[2 * j], samples[2 * j + 1]));
    loss += weights[i] * weights[i] * ray.length(samples[2 * i], samples[2 * i + 1]) / 3;
    if (ray.farField) loss += 2 * farWeightOf(weights) * weights[i] * std::abs(T(1) - mi);
  }
  return loss;
}

// dL/dw_i with T_final held fixed: 2 sum_j w_j |m_i - m_j| + 2/3 w_i l_i (+ 2 T_final |1 - m_i|
// with the far field; T_final's own part is distortionFarGradient).
template <class T>
std::vector<T> distortionWeightGradient(std::span<const T> samples, std::span<const T> weights, const DistortionRay<T>& ray) {
  const size_t n = samples.size() / 2;
  const T farWeight = ray.farField ? farWeightOf(weights) : T(0);
  std::vector<T> g(n);
  for (size_t i = 0; i < n; ++i) {
    const T mi = ray.midpoint(samples[2 * i], samples[2 * i + 1]);
    T sum = 0;
    for (size_t j = 0; j < n; ++j) sum += weights[j] * std::abs(mi - ray.midpoint(samples[2 * j], samples[2 * j + 1]));
    g[i] = 2 * sum + T(2) / 3 * weights[i] * ray.length(samples[2 * i], samples[2 * i + 1]) + 2 * farWeight * std::abs(T(1) - mi);
  }
  return g;
}

// dL/dT_final with the weights held fixed: 2 sum_i w_i |1 - m_i| with the far field, else 0.
template <class T>
T distortionFarGradient(std::span<const T> samples, std::span<const T> weights, const DistortionRay<T>& ray) {
  if (!ray.farField) return 0;
  T sum = 0;
  for (size_t i = 0; i < samples.size() / 2; ++i) sum += weights[i] * std::abs(T(1) - ray.midpoint(samples[2 * i], samples[2 * i + 1]));
  return 2 * sum;
}

}  // namespace vknerf::ref

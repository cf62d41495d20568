#pragma once
// CPU reference for shaders/render/composite_forward.comp and composite_backward.comp (one ray), in float
// or double. Inputs use the GPU layouts: samples are (t, delta) pairs, the field is
// (r, g, b, sigma) per sample with sigma already activated.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "reference/render/distortion_loss.h"

namespace vknerf::ref {

// Caps sigma * delta so that sigma = inf never becomes inf arithmetic (see shaders/render/composite.glsl).
inline constexpr double kMaxOpticalDepth = 1e30;

template <class T> T opticalDepth(T sigma, T delta) {
  return delta > T(0) ? std::min(sigma * delta, T(kMaxOpticalDepth)) : T(0);
}

// 1 - exp(-x) without cancellation for tiny x.
template <class T> T alphaOf(T x) { return -std::expm1(-x); }

template <class T> struct RayColor {
  std::array<T, 3> rgb{};  // sum w_i c_i + T_final * bg
  T opacity = 0;           // 1 - T_final
  T depth = 0;             // sum w_i t_i, not normalised
  std::vector<T> weights;  // w_i = T_i alpha_i
};

template <class T>
RayColor<T> compositeForward(std::span<const T> samples, std::span<const T> field, const std::array<T, 3>& bg) {
  size_t n = samples.size() / 2;
  RayColor<T> out;
  out.weights.resize(n);
  T prefix = 0;  // S_i: exclusive prefix sum of the optical depths
  for (size_t i = 0; i < n; ++i) {
    T x = opticalDepth(field[4 * i + 3], samples[2 * i + 1]);
    T w = std::exp(-prefix) * alphaOf(x);
    out.weights[i] = w;
    for (int k = 0; k < 3; ++k) out.rgb[k] += w * field[4 * i + k];
    out.depth += w * samples[2 * i];
    prefix += x;
  }
  T escape = std::exp(-prefix);
  for (int k = 0; k < 3; ++k) out.rgb[k] += escape * bg[k];
  out.opacity = alphaOf(prefix);
  return out;
}

// dL/d(r, g, b, sigma) per sample given dL/d(r, g, b, opacity) and dL/ddepth of the ray, plus
// `distortion` times the distortion loss's gradient (distances normalised by `ray`). The suffix
// sums R_i = sum_{j>i} w_j c_j + T_final bg are carried back to front as Q_i = R_i / T_{i+1}, a convex mix of colours, so nothing
// cancels when T underflows (derivation in composite_backward.comp). A loss g(w) of the weights
// reaches sigma_k as delta_k (g_k T_{k+1} - sum_{i>k} g_i w_i), g_i = dL/dw_i: w_k grows with
// sigma_k by delta_k T_{k+1}, every w_i behind it shrinks by delta_k w_i.
template <class T>
std::vector<std::array<T, 4>> compositeBackward(std::span<const T> samples, std::span<const T> field,
                                                const std::array<T, 3>& bg, const std::array<T, 4>& dColor,
                                                T dDepth, T distortion = 0,
                                                const DistortionRay<T>& ray = {}) {
  size_t n = samples.size() / 2;
  std::vector<T> tOut(n), weight(n), alpha(n);
  T prefix = 0, tIn = 1;
  for (size_t i = 0; i < n; ++i) {
    T x = opticalDepth(field[4 * i + 3], samples[2 * i + 1]);
    alpha[i] = alphaOf(x);
    weight[i] = tIn * alpha[i];
    prefix += x;
    tOut[i] = std::exp(-prefix);
    tIn = tOut[i];
  }
  std::vector<std::array<T, 4>> grad(n);
  std::vector<T> gDistortion(n, T(0));
  // With the far field in the loss, T_final = exp(-sum_k x_k) reaches every sigma_k as
  // -delta_k T_final dL/dT_final.
  T farTerm = 0;
  if (distortion != 0) {
    gDistortion = distortionWeightGradient<T>(samples, weight, ray);
    for (T& g : gDistortion) g *= distortion;
    farTerm = distortion * distortionFarGradient<T>(samples, weight, ray) * tIn;
  }
  T suffix = 0;  // sum_{i>k} gDistortion_i w_i
  T opacityTerm = dColor[3] * tIn;
  std::array<T, 3> q = bg;
  T qDepth = 0;
  for (size_t i = n; i-- > 0;) {
    const T* c = &field[4 * i];
    T t = samples[2 * i], delta = samples[2 * i + 1];
    T colorTerm = 0;
    for (int k = 0; k < 3; ++k) colorTerm += dColor[k] * (c[k] - q[k]);
    T inner = tOut[i] * (colorTerm + dDepth * (t - qDepth)) + opacityTerm + gDistortion[i] * tOut[i] - suffix - farTerm;
    suffix += gDistortion[i] * weight[i];
    grad[i] = {weight[i] * dColor[0], weight[i] * dColor[1], weight[i] * dColor[2], delta * inner};
    T survive = std::exp(-opticalDepth(field[4 * i + 3], delta));
    for (int k = 0; k < 3; ++k) q[k] = alpha[i] * c[k] + survive * q[k];
    qDepth = alpha[i] * t + survive * qDepth;
  }
  return grad;
}

}  // namespace vknerf::ref

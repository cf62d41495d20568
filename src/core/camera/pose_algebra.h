#pragma once
// The pose algebra of camera refinement (shaders/rays/so3.glsl, camera_correct.comp): a camera's
// learned correction (w, tau), 6 numbers, turns its camera-to-world pose [R | c] into
// [exp(w) R | c + tau] (nerfstudio's SO3xR3, in the world frame). In float or double; the host uses
// it to write the refined poses, the tests as the oracle.
#include <array>
#include <cmath>

namespace vknerf::core {

template <class T> using Mat3 = std::array<T, 9>;  // row-major

// a = sin t / t, b = (1 - cos t) / t^2, c = (t - sin t) / t^3 of t = |w|, from their series near 0
// (the shader's threshold).
template <class T>
std::array<T, 3> so3Coefficients(const T* w) {
  const T t2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
  if (t2 < T(1e-6)) return {T(1) - t2 / T(6), T(0.5) - t2 / T(24), T(1) / T(6) - t2 / T(120)};
  const T t = std::sqrt(t2);
  return {std::sin(t) / t, (T(1) - std::cos(t)) / t2, (t - std::sin(t)) / (t2 * t)};
}

// I + x K + y K^2 with K = [w]x.
template <class T>
Mat3<T> so3Series(const T* w, T x, T y) {
  const Mat3<T> K{0, -w[2], w[1], w[2], 0, -w[0], -w[1], w[0], 0};
  Mat3<T> out{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      T kk = 0;
      for (int k = 0; k < 3; ++k) kk += K[3 * i + k] * K[3 * k + j];
      out[3 * i + j] = (i == j ? T(1) : T(0)) + x * K[3 * i + j] + y * kk;
    }
  return out;
}

template <class T> Mat3<T> so3Exp(const T* w) {
  const auto k = so3Coefficients(w);
  return so3Series(w, k[0], k[1]);
}

// d(exp(w) v) / dw = -[exp(w) v]x J_l(w).
template <class T> Mat3<T> so3LeftJacobian(const T* w) {
  const auto k = so3Coefficients(w);
  return so3Series(w, k[1], k[2]);
}

// The camera-to-world matrix (row-major 4x4, or its first 12 numbers) with correction
// (w0, w1, w2, tau0, tau1, tau2) applied; the bottom row is copied.
template <class T, class M>
std::array<T, 16> correctedPose(const M& c2w, const T* correction) {
  const Mat3<T> E = so3Exp(correction);
  std::array<T, 16> out{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      T v = 0;
      for (int k = 0; k < 3; ++k) v += E[3 * i + k] * T(c2w[4 * k + j]);
      out[4 * i + j] = v;
    }
    out[4 * i + 3] = T(c2w[4 * i + 3]) + correction[3 + i];
  }
  if (c2w.size() >= 16)
    for (int j = 0; j < 4; ++j) out[12 + j] = T(c2w[12 + j]);
  return out;
}

}  // namespace vknerf::core

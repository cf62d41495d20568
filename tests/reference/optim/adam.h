#pragma once
// CPU reference for shaders/optim/adam.comp, in float or double.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

namespace vknerf::ref {

template <class T> struct AdamParams {
  T beta1 = T(0.9), beta2 = T(0.999), epsilon = T(1e-8);
  size_t skipZeroGradientsFrom = SIZE_MAX;  // parameters at and past it with a zero gradient are skipped
};

// One Adam step (Kingma & Ba, with bias correction) at 1-based step t and learning rate lr:
//   m = b1 m + (1 - b1) g,  v = b2 v + (1 - b2) g^2,
//   p -= lr * (m / (1 - b1^t)) / (sqrt(v / (1 - b2^t)) + eps),  then g = 0.
// A parameter at or past skipZeroGradientsFrom whose gradient is exactly 0 is left entirely
// untouched (p, m and v), as sparse hash-grid rows want.
template <class T>
void adamStep(std::span<T> params, std::span<T> grads, std::span<T> m, std::span<T> v, uint32_t t, T lr,
              const AdamParams<T>& a) {
  const T c1 = T(1) / (T(1) - std::pow(a.beta1, T(t)));
  const T c2 = T(1) / (T(1) - std::pow(a.beta2, T(t)));
  for (size_t i = 0; i < params.size(); ++i) {
    T g = grads[i];
    if (i >= a.skipZeroGradientsFrom && g == T(0)) continue;
    m[i] = a.beta1 * m[i] + (T(1) - a.beta1) * g;
    v[i] = a.beta2 * v[i] + (T(1) - a.beta2) * g * g;
    params[i] -= lr * (m[i] * c1) / (std::sqrt(v[i] * c2) + a.epsilon);
    grads[i] = T(0);
  }
}

// Exponential learning-rate decay, lr0 * rate^(step / steps), continuous in the step as in NeRF.
template <class T> T decayedLearningRate(T lr0, T rate, T steps, uint32_t step) {
  return lr0 * std::pow(rate, T(step) / steps);
}

}  // namespace vknerf::ref

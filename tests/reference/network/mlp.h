#pragma once
// CPU reference for the MLP shaders (mlp_*.comp), in float or double (T: arithmetic, P: parameter
// storage, double for finite differences). The flat parameter layout and the networks' shapes, which
// the GPU side (src/nerf/network/mlp.*) uses too, are production's (src/core/layouts/mlp_layout.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/layouts/mlp_layout.h"
#include "reference/rng.h"
#include "vknerf/density_activation.h"

namespace vknerf::ref {

using core::Activation;
using core::DenseMlpShape;
using core::DenseShape;
using core::initialParameters;
using core::layOut;
using core::NerfShape;
using core::pad4;

// The sigma head's activation is the public vknerf::DensityActivation (formulas there); TruncExp caps at this.
constexpr double kTruncExpCap = 15.0;
// Sigmoid arguments are clamped to +-kSigmoidClamp so exp() never overflows; sigmoid(80) is 1 in float.
constexpr double kSigmoidClamp = 80.0;

template <class T> T sigmoid(T x) {
  x = std::clamp(x, T(-kSigmoidClamp), T(kSigmoidClamp));
  return T(1) / (T(1) + std::exp(-x));
}

template <class T> T activate(Activation a, T z) {
  switch (a) {
    case Activation::Relu: return z > T(0) ? z : T(0);
    case Activation::Sigmoid: return sigmoid(z);
    default: return z;
  }
}
// Derivative expressed through the output y = act(z): ReLU's is [y > 0] (0 at z = 0).
template <class T> T activateGrad(Activation a, T y) {
  switch (a) {
    case Activation::Relu: return y > T(0) ? T(1) : T(0);
    case Activation::Sigmoid: return y * (T(1) - y);
    default: return T(1);
  }
}

template <class T> T density(DensityActivation a, T x) {
  switch (a) {
    case DensityActivation::TruncExp: return std::exp(std::min(x, T(kTruncExpCap)));
    case DensityActivation::Softplus: return std::max(x, T(0)) + std::log1p(std::exp(-std::fabs(x)));
    default: return x > T(0) ? x : T(0);
  }
}
template <class T> T densityGrad(DensityActivation a, T x) {
  switch (a) {
    case DensityActivation::TruncExp: return std::exp(std::clamp(x, T(-kTruncExpCap), T(kTruncExpCap)));
    case DensityActivation::Softplus: return sigmoid(x);
    default: return x > T(0) ? T(1) : T(0);
  }
}

// One sample through one layer: y[0..n) from a[0..ka), b[0..kb). Accumulates in T.
template <class T, class P>
void denseForward(const DenseShape& l, const std::vector<P>& p, const T* a, const T* b, T* y, bool applyAct = true) {
  for (uint32_t n = 0; n < l.n; ++n) {
    T z = T(p[l.biasOffset() + n]);
    for (uint32_t k = 0; k < l.ka; ++k) z += a[k] * T(p[l.offset + uint64_t(l.rowA(k)) * l.n4() + n]);
    for (uint32_t k = 0; k < l.kb; ++k) z += b[k] * T(p[l.offset + uint64_t(l.rowB(k)) * l.n4() + n]);
    y[n] = applyAct ? activate(l.act, z) : z;
  }
}

// Given dz = dL/d(pre-activation) for one sample: grads += outer(x, dz), bias += dz; da/db (if non-null)
// = dz W^T (overwritten, not accumulated).
template <class T, class P>
void denseBackward(const DenseShape& l, const std::vector<P>& p, const T* a, const T* b, const T* dz, std::vector<T>& g,
                   T* da, T* db) {
  for (uint32_t n = 0; n < l.n; ++n) {
    g[l.biasOffset() + n] += dz[n];
    for (uint32_t k = 0; k < l.ka; ++k) g[l.offset + uint64_t(l.rowA(k)) * l.n4() + n] += a[k] * dz[n];
    for (uint32_t k = 0; k < l.kb; ++k) g[l.offset + uint64_t(l.rowB(k)) * l.n4() + n] += b[k] * dz[n];
  }
  auto back = [&](uint32_t kCount, auto row, T* dx) {
    if (!dx) return;
    for (uint32_t k = 0; k < kCount; ++k) {
      T s = 0;
      for (uint32_t n = 0; n < l.n; ++n) s += dz[n] * T(p[l.offset + uint64_t(row(k)) * l.n4() + n]);
      dx[k] = s;
    }
  };
  back(l.ka, [&](uint32_t k) { return l.rowA(k); }, da);
  back(l.kb, [&](uint32_t k) { return l.rowB(k); }, db);
}

// ---------------------------------------------------------------------------------------------
// The NeRF network (seed §4.8, §6.4): its layers, NerfShape, in src/core/layouts/mlp_layout.h.
template <class T> struct NerfSample {
  std::vector<std::vector<T>> h;  // trunk outputs
  std::vector<T> f;               // feature (V) and sigma pre-activation (index V)
  std::vector<T> c;               // colour hidden
  std::array<T, 4> out{};         // rgb, sigma
};

template <class T, class P>
NerfSample<T> nerfForward(const NerfShape& s, const std::vector<P>& p, const T* pos, const T* dir) {
  NerfSample<T> r;
  r.h.resize(s.depth);
  for (uint32_t l = 0; l < s.depth; ++l) {
    r.h[l].resize(s.width);
    const T* a = l == 0 ? pos : r.h[l - 1].data();
    denseForward(s.trunk(l), p, a, pos, r.h[l].data());
  }
  r.f.resize(s.featureWidth + 1);
  denseForward(s.feature(), p, r.h.back().data(), (const T*)nullptr, r.f.data());
  r.c.resize(s.width / 2);
  denseForward(s.colour(), p, r.f.data(), dir, r.c.data());
  T rgb[3];
  denseForward(s.head(), p, r.c.data(), (const T*)nullptr, rgb);
  r.out = {rgb[0], rgb[1], rgb[2], density(s.density, r.f[s.featureWidth])};
  return r;
}

// Accumulates dL/dparams into g (sized s.total) for one sample; dPos/dDir (posDims/dirDims, may be null)
// receive dL/dgamma(x), dL/dgamma(d); dColour (width / 2, may be null) dL/d(the colour layer's
// pre-activation).
template <class T, class P>
void nerfBackward(const NerfShape& s, const std::vector<P>& p, const T* pos, const T* dir, const NerfSample<T>& fw,
                  const std::array<T, 4>& dOut, std::vector<T>& g, T* dPos, T* dDir, T* dColour = nullptr) {
  const uint32_t W = s.width, V = s.featureWidth;
  T dzHead[3];
  for (int i = 0; i < 3; ++i) dzHead[i] = dOut[i] * activateGrad(Activation::Sigmoid, fw.out[i]);
  std::vector<T> dc(W / 2), df(V + 1), dh(W), dhPrev(W), dPosPart(s.posDims);
  denseBackward(s.head(), p, fw.c.data(), (const T*)nullptr, dzHead, g, dc.data(), (T*)nullptr);
  for (uint32_t k = 0; k < W / 2; ++k) dc[k] *= activateGrad(Activation::Relu, fw.c[k]);
  if (dColour) std::copy(dc.begin(), dc.end(), dColour);
  denseBackward(s.colour(), p, fw.f.data(), dir, dc.data(), g, df.data(), dDir);
  df[V] = dOut[3] * densityGrad(s.density, fw.f[V]);
  denseBackward(s.feature(), p, fw.h.back().data(), (const T*)nullptr, df.data(), g, dh.data(), (T*)nullptr);
  if (dPos) std::fill(dPos, dPos + s.posDims, T(0));
  for (uint32_t l = s.depth; l-- > 0;) {
    for (uint32_t k = 0; k < W; ++k) dh[k] *= activateGrad(Activation::Relu, fw.h[l][k]);
    if (l == 0) {
      denseBackward(s.trunk(0), p, pos, (const T*)nullptr, dh.data(), g, dPos ? dPosPart.data() : nullptr, (T*)nullptr);
    } else {
      denseBackward(s.trunk(l), p, fw.h[l - 1].data(), pos, dh.data(), g, dhPrev.data(),
                    dPos && s.trunk(l).kb ? dPosPart.data() : nullptr);
      std::swap(dh, dhPrev);
    }
    if (dPos && (l == 0 || s.trunk(l).kb))
      for (uint32_t k = 0; k < s.posDims; ++k) dPos[k] += dPosPart[k];
  }
}

// ---------------------------------------------------------------------------------------------
// A plain MLP (DenseMlpShape, src/core/layouts/mlp_layout.h): inputs -> hidden layers of `width` with
// ReLU -> outputs with sigmoid.
template <class T, class P>
std::vector<std::vector<T>> denseMlpForward(const DenseMlpShape& s, const std::vector<P>& p, const T* in) {
  std::vector<std::vector<T>> acts;  // one per layer, the last is the output
  const T* x = in;
  for (const auto& l : s.layers) {
    acts.emplace_back(l.n);
    denseForward(l, p, x, (const T*)nullptr, acts.back().data());
    x = acts.back().data();
  }
  return acts;
}

template <class T, class P>
void denseMlpBackward(const DenseMlpShape& s, const std::vector<P>& p, const T* in, const std::vector<std::vector<T>>& acts,
                      const T* dOut, std::vector<T>& g, T* dIn) {
  std::vector<T> dz(dOut, dOut + s.outputs), dx;
  for (size_t i = s.layers.size(); i-- > 0;) {
    const auto& l = s.layers[i];
    for (uint32_t n = 0; n < l.n; ++n) dz[n] *= activateGrad(l.act, acts[i][n]);
    dx.assign(l.ka, T(0));
    denseBackward(l, p, i ? acts[i - 1].data() : in, (const T*)nullptr, dz.data(), g, (i || dIn) ? dx.data() : nullptr,
                  (T*)nullptr);
    if (i == 0 && dIn) std::copy(dx.begin(), dx.end(), dIn);
    dz = dx;
  }
}

}  // namespace vknerf::ref

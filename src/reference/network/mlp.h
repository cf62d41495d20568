#pragma once
// CPU reference for the MLP shaders (mlp_*.comp), in float or double (T: arithmetic, P: parameter
// storage, double for finite differences), and the one definition of the
// flat parameter layout that the GPU side (src/nerf/network/mlp.*) uses too.
//
// Every network is a list of dense layers y = act(concat(a, b) W + bias). In the flat buffer a layer
// is W, row-major [ka4 + kb4][n4], then bias [n4]; ka4, kb4, n4 are the input/output widths rounded
// up to 4 (vec4 loads). Padding rows/columns are initialised to zero and stay zero under training:
// padding input columns are zero by contract, padding outputs get zero upstream gradient, so their
// gradients are exactly zero.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "reference/rng.h"
#include "vknerf/density_activation.h"

namespace vknerf::ref {

enum class Activation : uint32_t { None = 0, Relu = 1, Sigmoid = 2 };

// The sigma head's activation is the public vknerf::DensityActivation (formulas there); TruncExp caps at this.
constexpr double kTruncExpCap = 15.0;
// Sigmoid arguments are clamped to +-kSigmoidClamp so exp() never overflows; sigmoid(80) is 1 in float.
constexpr double kSigmoidClamp = 80.0;

inline uint32_t pad4(uint32_t n) { return (n + 3u) / 4u * 4u; }

struct DenseShape {
  uint32_t ka = 0, kb = 0, n = 0;  // true widths of input a, input b (0: none) and output
  Activation act = Activation::None;
  uint64_t offset = 0;  // float offset of W in the flat buffer (multiple of 4)
  uint32_t ka4() const { return pad4(ka); }
  uint32_t kb4() const { return pad4(kb); }
  uint32_t k4() const { return ka4() + kb4(); }
  uint32_t n4() const { return pad4(n); }
  uint64_t biasOffset() const { return offset + uint64_t(k4()) * n4(); }
  uint64_t floats() const { return uint64_t(k4() + 1) * n4(); }
  // Row of W for input column k of a (k < ka) or of b (ka4 <= row, k < kb).
  uint32_t rowA(uint32_t k) const { return k; }
  uint32_t rowB(uint32_t k) const { return ka4() + k; }
};

// Lays layers out back to back; returns the total float count.
inline uint64_t layOut(std::vector<DenseShape>& layers) {
  uint64_t off = 0;
  for (auto& l : layers) {
    l.offset = off;
    off += l.floats();
  }
  return off;
}

// PyTorch's nn.Linear default: weights and biases uniform in +-1/sqrt(fan_in), fan_in = ka + kb (true
// widths); padding entries zero. Entry i of the flat buffer draws rng01(seed, i, 0): deterministic.
inline std::vector<float> initialParameters(const std::vector<DenseShape>& layers, uint64_t total, uint32_t seed) {
  std::vector<float> p(total, 0.0f);
  for (const auto& l : layers) {
    double bound = 1.0 / std::sqrt(double(l.ka + l.kb));
    auto draw = [&](uint64_t i) { p[i] = float((2.0 * rng01(seed, uint32_t(i), 0) - 1.0) * bound); };
    for (uint32_t n = 0; n < l.n; ++n) {
      for (uint32_t k = 0; k < l.ka; ++k) draw(l.offset + uint64_t(l.rowA(k)) * l.n4() + n);
      for (uint32_t k = 0; k < l.kb; ++k) draw(l.offset + uint64_t(l.rowB(k)) * l.n4() + n);
      draw(l.biasOffset() + n);
    }
  }
  return p;
}

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
// The NeRF network (seed §4.8, §6.4).
//   trunk:   h0 = relu(L0 gamma(x));  h_l = relu(L_l concat(h_{l-1}, gamma(x) if l == skipLayer else -))
//   feature: f = F h_{D-1}, one layer W -> V+1: columns [0, V) the feature, column V the sigma
//            pre-activation (so the sigma head shares the feature layer's pass over h_{D-1})
//   colour:  c = relu(C concat(f[0, V), gamma(d)));  rgb = sigmoid(H c)  (W/2 -> 3)
//   output:  vec4(rgb, density(f[V]))
// V, the feature width, is W in the paper's network; instant-ngp passes 15 values + the density
// on to its colour network, so a hash-grid model can use a narrow V (a multiple of 4: the sigma
// column is read as a vec4).
struct NerfShape {
  uint32_t depth = 8, width = 256, skipLayer = 5, posDims = 63, dirDims = 27, featureWidth = 256;
  DensityActivation density = DensityActivation::Relu;

  std::vector<DenseShape> layers;  // trunk 0..depth-1, then feature, colour, head
  uint64_t total = 0;

  static NerfShape make(uint32_t depth, uint32_t width, uint32_t skipLayer, uint32_t posDims, uint32_t dirDims,
                        DensityActivation density, uint32_t featureWidth = 0) {
    if (depth < 1) throw std::invalid_argument("NeRF MLP: depth must be >= 1");
    if (width < 8 || width % 8) throw std::invalid_argument("NeRF MLP: width must be a positive multiple of 8");
    if (skipLayer >= depth) throw std::invalid_argument("NeRF MLP: skipLayer must be 0 (none) or < depth");
    if (posDims == 0 || dirDims == 0) throw std::invalid_argument("NeRF MLP: posDims and dirDims must be > 0");
    if (featureWidth == 0) featureWidth = width;
    if (featureWidth % 4 || featureWidth > width)
      throw std::invalid_argument("NeRF MLP: the feature width must be a positive multiple of 4, at most the width");
    NerfShape s;
    s.depth = depth, s.width = width, s.skipLayer = skipLayer, s.posDims = posDims, s.dirDims = dirDims;
    s.density = density, s.featureWidth = featureWidth;
    s.layers.push_back({posDims, 0, width, Activation::Relu});
    for (uint32_t l = 1; l < depth; ++l)
      s.layers.push_back({width, l == skipLayer ? posDims : 0u, width, Activation::Relu});
    s.layers.push_back({width, 0, featureWidth + 1, Activation::None});
    s.layers.push_back({featureWidth, dirDims, width / 2, Activation::Relu});
    s.layers.push_back({width / 2, 0, 3, Activation::Sigmoid});
    s.total = layOut(s.layers);
    return s;
  }
  const DenseShape& trunk(uint32_t l) const { return layers[l]; }
  const DenseShape& feature() const { return layers[depth]; }
  const DenseShape& colour() const { return layers[depth + 1]; }
  const DenseShape& head() const { return layers[depth + 2]; }
};

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
// A plain MLP: inputs -> hidden layers of `width` with ReLU -> outputs with sigmoid.
struct DenseMlpShape {
  uint32_t inputs = 2, width = 128, hiddenLayers = 2, outputs = 3;
  std::vector<DenseShape> layers;
  uint64_t total = 0;

  static DenseMlpShape make(uint32_t inputs, uint32_t width, uint32_t hiddenLayers, uint32_t outputs) {
    if (inputs == 0 || outputs == 0 || hiddenLayers == 0 || width == 0 || width % 4)
      throw std::invalid_argument("dense MLP: inputs, outputs, hidden layers must be > 0 and width a multiple of 4");
    DenseMlpShape s{inputs, width, hiddenLayers, outputs, {}, 0};
    s.layers.push_back({inputs, 0, width, Activation::Relu});
    for (uint32_t l = 1; l < hiddenLayers; ++l) s.layers.push_back({width, 0, width, Activation::Relu});
    s.layers.push_back({width, 0, outputs, Activation::Sigmoid});
    s.total = layOut(s.layers);
    return s;
  }
};

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

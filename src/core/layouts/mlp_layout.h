#pragma once
// The one definition of the flat parameter layout of the MLPs, which the GPU side
// (src/nerf/network/mlp.*) and the CPU reference (tests/reference/network/mlp.h) share, and of the
// networks' shapes.
//
// Every network is a list of dense layers y = act(concat(a, b) W + bias). In the flat buffer a layer
// is W, row-major [ka4 + kb4][n4], then bias [n4]; ka4, kb4, n4 are the input/output widths rounded
// up to 4 (vec4 loads). Padding rows/columns are initialised to zero and stay zero under training:
// padding input columns are zero by contract, padding outputs get zero upstream gradient, so their
// gradients are exactly zero.
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "core/math/rng.h"
#include "vknerf/density_activation.h"

namespace vknerf::core {

enum class Activation : uint32_t { None = 0, Relu = 1, Sigmoid = 2 };

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

}  // namespace vknerf::core

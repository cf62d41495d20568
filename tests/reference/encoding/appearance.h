#pragma once
// CPU reference for the appearance embedding (shaders/encoding/appearance_*.comp): a learned vector
// a of `dims` floats per training photo and its weights W_a (dims rows of the colour layer's
// `width`), which enter the colour layer as the bias a W_a on its pre-activation: the function of
// the vector as input columns of that layer beside the direction encoding.
//   bias:     a photo's bias row, vectors[photo] W_a
//   gradient: per photo, g = the sum of dL/d(colour pre-activation) over the rows of its rays; then
//             dL/da = W_a g and dL/dW_a = sum over photos of a (outer) g
//   mean:     the mean of the photos' vectors (what a novel view uses)
// Tables are row-major: `dims` floats per photo, `width` per row of W_a, of a bias and of dColour.
#include <cstdint>
#include <vector>

#include "core/layouts/appearance_layout.h"
#include "reference/rng.h"

namespace vknerf::ref {

// W_a at the start: production's (src/core/layouts/appearance_layout.h).
using core::appearanceWeights;

// Rows [0, count) (width each): vectors [first, first + count) times W_a, in double.
inline std::vector<double> appearanceBias(const std::vector<float>& vectors, const std::vector<float>& weights,
                                          uint32_t dims, uint32_t width, uint32_t first, uint32_t count) {
  std::vector<double> b(size_t(count) * width, 0.0);
  for (uint32_t p = 0; p < count; ++p)
    for (uint32_t k = 0; k < dims; ++k)
      for (uint32_t n = 0; n < width; ++n)
        b[size_t(p) * width + n] += double(vectors[size_t(first + p) * dims + k]) * weights[size_t(k) * width + n];
  return b;
}

struct AppearanceGradient {
  std::vector<double> photoSums;  // g: width per photo
  std::vector<double> vectors;    // dL/da: dims per photo
  std::vector<double> weights;    // dL/dW_a: dims rows of width
};

// From dColour (width values a row) over the first `rays` rays, ray r of photo rayPhoto[r] owning
// rows [rowOffsets[r], rowOffsets[r + 1]).
template <class T>
AppearanceGradient appearanceGradient(const std::vector<T>& dColour, uint32_t width,
                                             const std::vector<uint32_t>& rayPhoto,
                                             const std::vector<uint32_t>& rowOffsets, uint32_t rays,
                                             uint32_t numPhotos, const std::vector<float>& vectors,
                                             const std::vector<float>& weights, uint32_t dims) {
  AppearanceGradient g{std::vector<double>(size_t(numPhotos) * width, 0.0),
                       std::vector<double>(size_t(numPhotos) * dims, 0.0),
                       std::vector<double>(size_t(dims) * width, 0.0)};
  for (uint32_t r = 0; r < rays; ++r)
    for (uint32_t q = rowOffsets[r]; q < rowOffsets[r + 1]; ++q)
      for (uint32_t n = 0; n < width; ++n) g.photoSums[size_t(rayPhoto[r]) * width + n] += dColour[size_t(q) * width + n];
  for (uint32_t c = 0; c < numPhotos; ++c)
    for (uint32_t k = 0; k < dims; ++k)
      for (uint32_t n = 0; n < width; ++n) {
        const double s = g.photoSums[size_t(c) * width + n];
        g.vectors[size_t(c) * dims + k] += double(weights[size_t(k) * width + n]) * s;
        g.weights[size_t(k) * width + n] += double(vectors[size_t(c) * dims + k]) * s;
      }
  return g;
}

inline std::vector<double> appearanceMean(const std::vector<float>& table, uint32_t dims, uint32_t numPhotos) {
  std::vector<double> m(dims, 0.0);
  for (uint32_t c = 0; c < numPhotos; ++c)
    for (uint32_t k = 0; k < dims; ++k) m[k] += table[size_t(c) * dims + k];
  for (double& v : m) v = numPhotos ? v / numPhotos : 0.0;
  return m;
}

}  // namespace vknerf::ref

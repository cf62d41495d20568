#pragma once
// CPU reference for the appearance embedding (shaders/encoding/appearance_*.comp): a learned vector
// of `dims` floats per training photo, fed to the colour network beside the direction encoding.
//   rows:     each sample's row gets the vector of its ray's photo (or one fixed table row)
//   gradient: per photo, the sum of dL/d(vector columns) over the rows of its rays
//   mean:     the mean of the photos' vectors (what a novel view uses)
// Tables are row-major, `dims` floats per photo; feature rows are `stride` floats, the vector at
// column `offset`.
#include <cstdint>
#include <vector>

namespace vknerf::ref {

// features[row * stride + offset + k] = table[photo * dims + k], photo = rayPhoto[sampleRay[row]],
// or `fixedRow` for every row when it is >= 0.
inline void appearanceRows(const std::vector<float>& table, uint32_t dims, const std::vector<uint32_t>& rayPhoto,
                           const std::vector<uint32_t>& sampleRay, uint32_t count, uint32_t stride, uint32_t offset,
                           int64_t fixedRow, std::vector<float>& features) {
  for (uint32_t row = 0; row < count; ++row) {
    const size_t photo = fixedRow >= 0 ? size_t(fixedRow) : rayPhoto[sampleRay[row]];
    for (uint32_t k = 0; k < dims; ++k) features[size_t(row) * stride + offset + k] = table[photo * dims + k];
  }
}

// Per photo (numPhotos x dims, in double): the sum over the first `rays` rays r of that photo of
// dDir[q * stride + offset + k] for q in [rowOffsets[r], rowOffsets[r + 1]).
inline std::vector<double> appearanceGradient(const std::vector<float>& dDir, uint32_t dims, uint32_t stride,
                                              uint32_t offset, const std::vector<uint32_t>& rayPhoto,
                                              const std::vector<uint32_t>& rowOffsets, uint32_t rays,
                                              uint32_t numPhotos) {
  std::vector<double> g(size_t(numPhotos) * dims, 0.0);
  for (uint32_t r = 0; r < rays; ++r)
    for (uint32_t q = rowOffsets[r]; q < rowOffsets[r + 1]; ++q)
      for (uint32_t k = 0; k < dims; ++k) g[size_t(rayPhoto[r]) * dims + k] += dDir[size_t(q) * stride + offset + k];
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

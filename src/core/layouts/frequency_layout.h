#pragma once
// The width of the frequency encoding gamma (src/nerf/encoding/frequency_encoding.h; CPU reference
// tests/reference/encoding/frequency_encoding.h, which gives the column order).
#include <cstdint>

namespace vknerf::core {

// Number of features gamma produces for `dims` input components.
inline uint32_t frequencyEncodingDims(uint32_t dims, uint32_t levels, bool includeInput) {
  return dims * (2 * levels + (includeInput ? 1 : 0));
}

}  // namespace vknerf::core

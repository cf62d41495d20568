#pragma once
// A colour channel in [0, 1] as a byte, as the exporters write it (non-finite reads as 0).
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace vknerf::detail {

inline uint8_t unitToByte(float v) {
  return uint8_t(std::lround(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f));
}

}  // namespace vknerf::detail

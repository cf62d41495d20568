#pragma once
// Which occupancy cells some training camera sees (instant-ngp's mark_untrained_density_grid): the
// oracle of shaders/occupancy/occupancy_mark_unseen.comp, cell by cell in the shader's float order.
// A camera's view, the pinhole bound that holds its lens, is production's
// (src/core/camera/view_bounds.h: the fast model sizes its grid with it).
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/camera/view_bounds.h"
#include "reference/rays/lens.h"

namespace vknerf::ref {

using core::kViewNearlySideways;
using core::kViewUnbounded;
using core::pixelTangents;
using core::pointSeen;
using core::ViewBound;
using core::viewBoundOf;
using core::viewBoundsOf;

// Corner k (bit 0: x, 1: y, 2: z) of cell i of C nested R^3 cascades in the world, for a scene box
// of centre `centre` and half extents `half` (cascade c spans 2^(c - C + 1) of it).
inline std::array<float, 3> cellCorner(uint32_t i, uint32_t k, uint32_t r, uint32_t cascades,
                                       const std::array<float, 3>& centre, const std::array<float, 3>& half) {
  const uint32_t perCascade = r * r * r, local = i % perCascade;
  const uint32_t c[3] = {local % r, (local / r) % r, local / (r * r)};
  const float scale = 1.0f / float(1u << (cascades - 1u - i / perCascade));
  std::array<float, 3> p;
  for (int a = 0; a < 3; ++a) {
    const float n = (float(c[a] + ((k >> a) & 1u)) * (2.0f / float(r)) - 1.0f) * scale;
    p[a] = centre[a] + n * half[a];
  }
  return p;
}

// A cell is seen when one of its 8 corners is in some camera's view.
inline bool cellSeen(std::span<const ViewBound> views, uint32_t i, uint32_t r, uint32_t cascades,
                     const std::array<float, 3>& centre, const std::array<float, 3>& half) {
  for (uint32_t k = 0; k < 8; ++k) {
    const auto p = cellCorner(i, k, r, cascades, centre, half);
    for (const ViewBound& v : views)
      if (pointSeen(v, p)) return true;
  }
  return false;
}

// The occupancy densities after marking: -1 (empty for good: the update keeps negative densities)
// in every cell no view sees, the others unchanged.
inline void markUnseenEmpty(std::span<const ViewBound> views, uint32_t r, uint32_t cascades,
                            const std::array<float, 3>& centre, const std::array<float, 3>& half,
                            std::vector<float>& density) {
  for (uint32_t i = 0; i < uint32_t(density.size()); ++i)
    if (!cellSeen(views, i, r, cascades, centre, half)) density[i] = -1.0f;
}

}  // namespace vknerf::ref

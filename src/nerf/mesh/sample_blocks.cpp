#include "nerf/mesh/sample_blocks.h"

#include <algorithm>
#include <cmath>

namespace vknerf::nerf {
namespace {

std::array<uint32_t, 3> blockCounts(const core::GridLayout& g) {
  std::array<uint32_t, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = (g.n[k] + kBlockSide - 1) / kBlockSide;
  return c;
}

}  // namespace

SampleBlocks allSampleBlocks(const core::GridLayout& layout) {
  SampleBlocks b;
  b.count = blockCounts(layout);
  b.ids.resize(size_t(b.count[0]) * b.count[1] * b.count[2]);
  for (size_t i = 0; i < b.ids.size(); ++i) b.ids[i] = uint32_t(i);
  return b;
}

SampleBlocks occupiedSampleBlocks(const core::GridLayout& g, const Aabb& box, const OccupancyBits& occ) {
  SampleBlocks b;
  b.count = blockCounts(g);
  std::vector<uint8_t> listed(size_t(b.count[0]) * b.count[1] * b.count[2], 0);
  const uint32_t r = occ.resolution, perCascade = r * r * r;
  for (uint32_t c = 0; c < occ.cascades; ++c) {
    // Cascade c spans [-h, h]^3 of the box mapped onto [-1, 1]^3 (nerf/occupancy/occupancy_grid.h).
    const double h = std::ldexp(1.0, int(c) - int(occ.cascades) + 1), cell = 2 * h / r;
    for (uint32_t i = 0; i < perCascade; ++i) {
      if (!occ.occupied(c * perCascade + i)) continue;
      const uint32_t idx[3] = {i % r, (i / r) % r, i / (r * r)};
      uint32_t lo[3], hi[3];
      bool inside = true;
      for (int k = 0; k < 3; ++k) {
        const double half = 0.5 * (double(box.max[k]) - box.min[k]);
        const double mid = 0.5 * (double(box.max[k]) + box.min[k]);
        const double x0 = mid + half * (-h + idx[k] * cell), x1 = mid + half * (-h + (idx[k] + 1) * cell);
        // Samples within one spacing (and one more for rounding) of the cell: the corners of every
        // grid cell that overlaps it.
        const double s0 = std::floor((x0 - g.origin[k]) / g.spacing[k]) - 1;
        const double s1 = std::ceil((x1 - g.origin[k]) / g.spacing[k]) + 1;
        if (s1 < 0 || s0 > double(g.n[k]) - 1) inside = false;
        lo[k] = uint32_t(std::clamp(s0, 0.0, double(g.n[k]) - 1)) / kBlockSide;
        hi[k] = uint32_t(std::clamp(s1, 0.0, double(g.n[k]) - 1)) / kBlockSide;
      }
      if (!inside) continue;
      for (uint32_t z = lo[2]; z <= hi[2]; ++z)
        for (uint32_t y = lo[1]; y <= hi[1]; ++y)
          for (uint32_t x = lo[0]; x <= hi[0]; ++x) listed[x + size_t(b.count[0]) * (y + size_t(b.count[1]) * z)] = 1;
    }
  }
  for (size_t i = 0; i < listed.size(); ++i)
    if (listed[i]) b.ids.push_back(uint32_t(i));
  return b;
}

}  // namespace vknerf::nerf

#include "api/fast_capacity.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "reference/occupancy/view_bounds.h"

namespace vknerf::nerf {
namespace {

constexpr double kCellsPerFootprint = 2.0;  // Nyquist
constexpr uint32_t kMinFinest = 64, kMaxFinest = 4096;
// A CPU device trains a few thousand steps in minutes, too few for levels much finer than this to
// pay. On the distorted unbounded capture (docs/unbounded.md): 500 steps at finest 256 gave
// 18.75 dB held-out against 18.28 dB at the rule's 4096, with the same 2^15 table; once the
// distortion loss kept fog out, 512 beat 256 by 0.44 dB at 120 s and 0.35 dB at 300 s, and 1024
// gained nothing at 120 s.
constexpr uint32_t kMaxFinestCpu = 512;
constexpr uint32_t kMinLog2Size = 15, kMaxLog2Size = 19, kMaxLog2SizeCpu = 15;
constexpr uint32_t kSeenGrid = 32;  // cells per axis of the box for the seen share

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Share of the box whose cell centres some camera sees (ref::viewBoundOf: in front, inside the image).
double seenShare(const Dataset& train) {
  const auto views = ref::viewBoundsOf(train.cameras);
  uint32_t seen = 0;
  for (uint32_t z = 0; z < kSeenGrid; ++z)
    for (uint32_t y = 0; y < kSeenGrid; ++y)
      for (uint32_t x = 0; x < kSeenGrid; ++x) {
        const uint32_t i[3] = {x, y, z};
        std::array<float, 3> p;
        for (int k = 0; k < 3; ++k)
          p[k] = train.bounds.min[k] + (float(i[k]) + 0.5f) / kSeenGrid * (train.bounds.max[k] - train.bounds.min[k]);
        for (const auto& v : views)
          if (ref::pointSeen(v, p)) {
            ++seen;
            break;
          }
      }
  return double(seen) / double(kSeenGrid * kSeenGrid * kSeenGrid);
}

uint32_t ceilPow2(double v) {
  uint32_t p = 1;
  while (p < kMaxFinest && double(p) < v) p *= 2;
  return p;
}

}  // namespace

std::string resolveFastCapacity(FastModel& m, const Dataset& train, bool cpuDevice) {
  if (m.hashGrowth != 0 && m.hashLog2Size != 0) return "";
  const Aabb& b = train.bounds;
  double extent = 0;
  std::array<double, 3> centre;
  for (int k = 0; k < 3; ++k) {
    extent = std::max(extent, double(b.max[k]) - b.min[k]);
    centre[k] = 0.5 * (double(b.min[k]) + b.max[k]);
  }
  std::vector<double> distances, footprints;
  for (const Camera& c : train.cameras) {
    const double dx = c.c2w[3] - centre[0], dy = c.c2w[7] - centre[1], dz = c.c2w[11] - centre[2];
    const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
    distances.push_back(d);
    footprints.push_back(d / std::sqrt(double(c.fx) * c.fy));  // the pixel angle is 1 / focal
  }
  const double distance = median(distances), footprint = median(footprints);
  char why[320];
  if (m.hashGrowth == 0) {
    const double wanted = footprint > 0 ? kCellsPerFootprint * extent / footprint : kMaxFinest;
    const uint32_t finest = std::clamp(ceilPow2(wanted), kMinFinest, cpuDevice ? kMaxFinestCpu : kMaxFinest);
    m.hashGrowth = m.hashLevels > 1 ? float(std::pow(double(finest) / m.hashBaseResolution, 1.0 / (m.hashLevels - 1))) : 1.0f;
    const std::string cap = cpuDevice ? "; at most " + std::to_string(kMaxFinestCpu) + " on a CPU" : "";
    std::snprintf(why, sizeof why, "finest %u (2 cells per pixel footprint %.3g at distance %.3g over the box's %.3g: %.0f%s)",
                  finest, footprint, distance, extent, wanted, cap.c_str());
  } else {
    std::snprintf(why, sizeof why, "finest %.0f (as configured)", m.hashBaseResolution * std::pow(double(m.hashGrowth), double(m.hashLevels - 1)));
  }
  std::string note = "fast model: hash grid " + std::to_string(m.hashLevels) + " levels, " + why;
  const double finest = m.hashBaseResolution * std::pow(double(m.hashGrowth), double(m.hashLevels - 1));
  if (m.hashLog2Size == 0) {
    double pixels = 0;
    for (const ImageRGBA8& im : train.images) pixels += double(im.width) * im.height;
    const double seen = seenShare(train);
    const double byPixels = std::floor(std::log2(std::max(1.0, pixels / (double(m.hashLevels) * m.hashFeatures))));
    const double byCells = std::ceil(std::log2(std::max(1.0, seen * finest * finest * finest)));
    const uint32_t most = cpuDevice ? kMaxLog2SizeCpu : kMaxLog2Size;
    m.hashLog2Size = uint32_t(std::clamp(std::min(byPixels, byCells), double(kMinLog2Size), double(most)));
    std::snprintf(why, sizeof why, ", 2^%u entries per level (%.2f M training pixels, a parameter each at most: 2^%.0f; %.0f%% of the box in view: 2^%.0f finest cells; at most 2^%u%s)",
                  m.hashLog2Size, pixels / 1e6, byPixels, 100.0 * seen, byCells, most, cpuDevice ? " on a CPU" : "");
  } else {
    std::snprintf(why, sizeof why, ", 2^%u entries per level (as configured)", m.hashLog2Size);
  }
  note += why;
  const double mib = double(m.hashLevels) * double(1u << m.hashLog2Size) * m.hashFeatures * 4.0 / double(1 << 20);
  std::snprintf(why, sizeof why, ": at most %.1f MiB of table", mib);
  return note + why;
}

}  // namespace vknerf::nerf

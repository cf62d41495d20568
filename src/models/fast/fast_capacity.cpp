#include "models/fast/fast_capacity.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "nerf/sampling/ray_marcher.h"
#include "core/camera/view_bounds.h"

namespace vknerf::models {
namespace {

constexpr double kCellsPerFootprint = 2.0;  // Nyquist
constexpr uint32_t kMinFinest = 64, kMaxFinest = 4096;
// A CPU device trains a few thousand steps in minutes, too few for levels much finer than this to
// pay. On the distorted unbounded capture (docs/unbounded.md): 500 steps at finest 256 gave
// 18.75 dB held-out against 18.28 dB at the rule's 4096, with the same 2^15 table; once the
// distortion loss kept fog out, 512 beat 256 by 0.44 dB at 120 s and 0.35 dB at 300 s, and 1024
// gained nothing at 120 s.
constexpr uint32_t kMaxFinestCpu = 512;
// A CPU device's cap was 2^15 while every ray marched 128 steps: no larger table paid in the
// minutes it trains. With the march step following the footprint (below), 2^17 does on the scenes
// whose pixels ask for it (docs/performance.md, "The 800x800 detailed object": +0.6 dB there at
// 256 steps); the sample scene's 40k pixels still ask for 2^15.
constexpr uint32_t kMinLog2Size = 15, kMaxLog2Size = 19, kMaxLog2SizeCpu = 17;
// The march step, where the configuration leaves it open: about this many pixel footprints of the
// typical camera, the power of two nearest it (the estimate is a median: a finer rounding would
// claim more than it knows), within [128, 1024] (instant-ngp's 1024), [128, 512] on a CPU. Measured
// at 240 s on the 800x800 detailed object, whose footprint is 1/1024 of the box diagonal: a step
// of 8 footprints (128 steps) 22.38 dB held-out, 4 (256) 22.90, 2 (512) 22.26; below 128 steps the
// sample scene (0.9 footprints at 128) lost to 128 (fewer samples, but the surfaces blur).
constexpr double kFootprintsPerStep = 4.0;
constexpr uint32_t kMinMarchSteps = 128, kMaxMarchSteps = 1024, kMaxMarchStepsCpu = 512;
// A step's samples, where the configuration leaves them open (a CPU device's default): 2^14, whatever
// the march steps. At 128 steps 2^14 beat 2^15 and 2^16 on the sample scene, and 2^15 lost 0.85 and
// 0.68 dB on the cup and fruit at 300 s (the distorted unbounded capture's 0.25 dB gain from 2^15 at
// 120 s was within its spread, docs/unbounded.md). At 256 steps the rule was once 2^15 (in
// proportion to the steps, to keep a step's rays), from the 800x800 object at 600 s, where 2^15 beat
// 2^14 by 0.14 dB; at the budgets this recipe is for, 2^14 won at 256 steps on every scene measured:
// flower (which marches 256) +0.64 dB at 150 s and +0.18 at 300 s, the cup marched at 256 +1.14 dB
// at 150 s, the sample scene marched at 256 +2.1 dB at 60 s (docs/real_captures.md, "A short budget
// on flower").
constexpr uint32_t kSamplesPerStep = 1u << 14;
// With the proposal a step's rays each take its samples, not the march's dozens: at 2^14 a step held
// five times the march's rays and cost half as much again; 2^13 won on cup, fruit and flower at
// 150 s (docs/real_captures.md, "The proposal at equal time").
constexpr uint32_t kSamplesPerProposalStep = 1u << 13;
constexpr uint32_t kSeenGrid = 32;  // cells per axis of the box for the seen share
// The occupancy grid's cells per axis, where the configuration leaves them open (a CPU device's
// default): half the march steps per diagonal, so that a cell spans about one step (1.15: an axis is
// the diagonal over sqrt(3)) whatever the march, and a ray that enters an occupied cell marches few
// empty samples before its surface; within [64, 256], [64, 128] on a CPU. Measured at 600 s on the
// 800x800 object (256 steps): two runs of 128^3 averaged 25.30 dB against 25.08 for two of 64^3
// (about +0.2 dB, the run-to-run spread), with more of the thin wires kept, once the occupancy
// update decayed each cell per measurement of it (OccupancyGrid::decayFor); before that it lost
// 0.58 to 0.81 dB. At 128 steps 128^3 did not pay: the cup even, the fruit (six cascades) -3.9 dB
// (docs/performance.md, "The occupancy grid follows the march step").
// With the proposal sampler the grid only says where a ray's candidates lie, and 64^3 on a CPU
// whatever the march: an update measures 2^16 cells, so a 128^3 cell of flower's four cascades is
// looked at once in about 2,000 steps and a 64^3 one eight times as often. At 300 s 64^3 won on
// flower (+0.28 dB, every held-out view, its depth whole where 128^3 left holes) and the cup at full
// size (docs/real_captures.md, "The occupancy grid under the proposal").
constexpr uint32_t kMarchStepsPerCell = 2;
constexpr uint32_t kMinGrid = 64, kMaxGrid = 256, kMaxGridCpu = 128, kMaxGridCpuProposal = 64;
// Where rays start, as a share of the inner cube's side: the same in any units. The vanilla model's
// fixed 0.05 (kNearPlane) is a hundredth of that cube in a scene of colmap2nerf's units, and a
// tenth of it in one of centimetres. Measured against 0.05 at 1500 steps: the cup 24.30 against
// 24.08 dB, the fruit 25.50 against 25.81 (within the runs' spread); on the wall capture 0.15 (this
// rule) and 0.3 gave the same 24.3 dB, so the near plane is not what its collapse needed.
constexpr double kNearShareOfInnerCube = 0.05;

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Share of the box whose cell centres some camera sees (core::viewBoundOf: in front, inside the image).
double seenShare(const Dataset& train) {
  const auto views = core::viewBoundsOf(train.cameras);
  uint32_t seen = 0;
  for (uint32_t z = 0; z < kSeenGrid; ++z)
    for (uint32_t y = 0; y < kSeenGrid; ++y)
      for (uint32_t x = 0; x < kSeenGrid; ++x) {
        const uint32_t i[3] = {x, y, z};
        std::array<float, 3> p;
        for (int k = 0; k < 3; ++k)
          p[k] = train.bounds.min[k] + (float(i[k]) + 0.5f) / kSeenGrid * (train.bounds.max[k] - train.bounds.min[k]);
        for (const auto& v : views)
          if (core::pointSeen(v, p)) {
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

// The largest side of the box and, the cascades nesting about its centre each half the side of the
// one around it, of the inner cube the cameras look into: the box over 2^(cascades - 1).
double extentOf(const Aabb& b) {
  double extent = 0;
  for (int k = 0; k < 3; ++k) extent = std::max(extent, double(b.max[k]) - b.min[k]);
  return extent;
}
double innerCubeOf(const FastModel& m, const Aabb& b) { return std::ldexp(extentOf(b), -int(std::max(m.cascades, 1u) - 1)); }

std::string resolveNearDistance(FastModel& m, const Aabb& box) {
  if (m.nearDistance != 0) return "";
  m.nearDistance = float(kNearShareOfInnerCube * innerCubeOf(m, box));
  char why[160];
  std::snprintf(why, sizeof why, "rays start %.3g in front of the camera (%.0f%% of the inner cube's side)", m.nearDistance,
                100 * kNearShareOfInnerCube);
  return why;
}

// The typical camera: the medians over the cameras of their distance to the box centre and of their
// pixel footprint there, distance / focal (the pixel angle is 1 / focal).
struct TypicalView {
  double distance = 0, footprint = 0;
};
TypicalView typicalViewOf(const Dataset& train) {
  const Aabb& b = train.bounds;
  std::array<double, 3> centre;
  for (int k = 0; k < 3; ++k) centre[k] = 0.5 * (double(b.min[k]) + b.max[k]);
  std::vector<double> distances, footprints;
  for (const Camera& c : train.cameras) {
    const double dx = c.c2w[3] - centre[0], dy = c.c2w[7] - centre[1], dz = c.c2w[11] - centre[2];
    const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
    distances.push_back(d);
    footprints.push_back(d / std::sqrt(double(c.fx) * c.fy));
  }
  return {median(distances), median(footprints)};
}

std::string resolveMarchSteps(FastModel& m, const Dataset& train, bool cpuDevice) {
  const bool open = m.marchSteps == 0;
  const double diagonal = nerf::RayMarcher::diagonal(nerf::RayMarcher::innerCube(train.bounds, std::max(m.cascades, 1u)));
  const double footprint = typicalViewOf(train).footprint;
  const double wanted = footprint > 0 ? diagonal / (kFootprintsPerStep * footprint) : kMaxMarchSteps;
  const uint32_t most = cpuDevice ? kMaxMarchStepsCpu : kMaxMarchSteps;
  if (open)
    m.marchSteps = uint32_t(std::clamp(std::exp2(std::round(std::log2(std::max(wanted, 1.0)))), double(kMinMarchSteps), double(most)));
  // A ray through the inner cube's diagonal takes every step; the cone steps of the outer cascades
  // (coneAngle) are fewer than that.
  if (m.maxSamplesPerRay == 0) m.maxSamplesPerRay = m.marchSteps;
  if (!open) return "";
  char why[240];
  std::snprintf(why, sizeof why,
                "march: %u steps per diagonal of the inner cube (%.3g over %.0f pixel footprints of %.3g: %.0f; within %u..%u%s), "
                "at most %u samples per ray",
                m.marchSteps, diagonal, kFootprintsPerStep, footprint, wanted, kMinMarchSteps, most, cpuDevice ? " on a CPU" : "",
                m.maxSamplesPerRay);
  return why;
}

std::string resolveGridResolution(FastModel& m, bool cpuDevice) {
  if (m.gridResolution != 0) return "";
  const bool proposalOnCpu = cpuDevice && m.usesProposal();
  const uint32_t most = proposalOnCpu ? kMaxGridCpuProposal : cpuDevice ? kMaxGridCpu : kMaxGrid;
  m.gridResolution = std::clamp(m.marchSteps / kMarchStepsPerCell, kMinGrid, most);
  char why[160];
  std::snprintf(why, sizeof why, "occupancy grid: %u^3 cells (half of %u march steps; within %u..%u%s)", m.gridResolution,
                m.marchSteps, kMinGrid, most, proposalOnCpu ? " with the proposal on a CPU" : cpuDevice ? " on a CPU" : "");
  return why;
}

std::string resolveSamplesPerStep(FastModel& m) {
  if (m.samplesPerBatch != 0) return "";
  char why[200];
  if (m.usesProposal()) {
    m.samplesPerBatch = kSamplesPerProposalStep;
    std::snprintf(why, sizeof why, "training step: about %u field samples, %u rays at the proposal's %u (more, cheaper steps)",
                  m.samplesPerBatch, m.samplesPerBatch / m.proposalSamples, m.proposalSamples);
    return why;
  }
  m.samplesPerBatch = kSamplesPerStep;
  std::snprintf(why, sizeof why, "training step: about %u marched samples (whatever the %u march steps: more, cheaper steps)",
                m.samplesPerBatch, m.marchSteps);
  return why;
}

std::string resolveHashGrid(FastModel& m, const Dataset& train, bool cpuDevice) {
  if (m.hashGrowth != 0 && m.hashLog2Size != 0) return "";
  const Aabb& b = train.bounds;
  const uint32_t doublings = std::max(m.cascades, 1u) - 1;
  const double inner = innerCubeOf(m, b);
  const auto [distance, footprint] = typicalViewOf(train);
  char why[400];
  if (m.hashGrowth == 0) {
    // The finest level resolves the inner cube at two cells per pixel footprint and spans the whole
    // box at that cell size (instant-ngp's 2048 x aabb_scale); one level more per cascade keeps the
    // levels' growth factor near a single cube's (the coarse levels serve the outer cascades).
    const double wanted = footprint > 0 ? kCellsPerFootprint * inner / footprint : kMaxFinest;
    const uint32_t finestInner = std::clamp(ceilPow2(wanted), kMinFinest, cpuDevice ? kMaxFinestCpu : kMaxFinest);
    // Contracted (FastModel::contraction), the grid spans twice the inner cube: one level more.
    const uint32_t spanDoublings = m.contraction && doublings > 0 ? 1 : doublings;
    const double finest = std::ldexp(double(finestInner), int(spanDoublings));
    m.hashLevels += spanDoublings;
    m.hashGrowth = m.hashLevels > 1 ? float(std::pow(finest / m.hashBaseResolution, 1.0 / (m.hashLevels - 1))) : 1.0f;
    const std::string cap = cpuDevice ? "; at most " + std::to_string(kMaxFinestCpu) + " on a CPU" : "";
    std::snprintf(why, sizeof why,
                  "finest %.0f over the %sbox: %u over its inner cube (2 cells per pixel footprint %.3g at distance %.3g over "
                  "the inner cube's %.3g: %.0f%s) times %u",
                  finest, spanDoublings != doublings ? "contracted " : "", finestInner, footprint, distance, inner, wanted,
                  cap.c_str(), 1u << spanDoublings);
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

}  // namespace

std::string resolveFastCapacity(FastModel& m, const Dataset& train, bool cpuDevice) {
  std::string note = resolveHashGrid(m, train, cpuDevice);
  for (const std::string& more :
       {resolveMarchSteps(m, train, cpuDevice), resolveSamplesPerStep(m), resolveGridResolution(m, cpuDevice),
        resolveNearDistance(m, train.bounds)})
    if (!more.empty()) note += (note.empty() ? "" : "\n") + more;
  return note;
}

}  // namespace vknerf::models

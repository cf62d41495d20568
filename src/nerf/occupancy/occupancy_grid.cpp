#include "nerf/occupancy/occupancy_grid.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/camera/view_bounds.h"
#include "vknerf/error.h"
#include "occupancy/occupancy_points_shared.h"
#include "occupancy/occupancy_splat_shared.h"
#include "occupancy/occupancy_ema_shared.h"
#include "occupancy/occupancy_mean_shared.h"
#include "occupancy/occupancy_count_shared.h"
#include "occupancy/occupancy_mark_unseen_shared.h"

namespace vknerf::nerf {
namespace {

using PointsPush = glsl::OccupancyPointsPush;
using SplatPush = glsl::OccupancySplatPush;
using EmaPush = glsl::OccupancyEmaPush;
using MeanPush = glsl::OccupancyMeanPush;
using CountPush = glsl::OccupancyCountPush;
using UnseenPush = glsl::OccupancyUnseenPush;

constexpr uint32_t kPointsLocal = 256, kSplatLocal = 256, kEmaLocal = 64, kCountLocal = 64, kCountWords = 16,
                   kUnseenLocal = 64;

void requireBytes(const char* what, const gpu::BufferRange& r, uint64_t needed) {
  gpu::requireBytes("OccupancyGrid", what, r, needed);
}

uint32_t checkedCells(uint32_t r, uint32_t cascades) {
  // 2^24 floats is 64 MiB, inside lavapipe's 128 MiB storage-buffer range.
  if (r < 1 || r > 256) throw Error("OccupancyGrid: resolution " + std::to_string(r) + " is outside [1, 256]");
  if (cascades < 1 || cascades > OccupancyGrid::kMaxCascades)
    throw Error("OccupancyGrid: " + std::to_string(cascades) + " cascades are outside [1, " + std::to_string(OccupancyGrid::kMaxCascades) + "]");
  if (uint64_t(r) * r * r * cascades > (1u << 24))
    throw Error("OccupancyGrid: " + std::to_string(cascades) + " cascades of " + std::to_string(r) +
                "^3 cells exceed 2^24 cells");
  return r * r * r * cascades;
}

}  // namespace

OccupancyGrid::OccupancyGrid(Context& ctx, uint32_t resolution, uint32_t cascades)
    : ctx_(ctx),
      resolution_(resolution),
      cascades_(cascades),
      numCells_(checkedCells(resolution, cascades)),
      // The densities and fresh measurements hold whole 32-cell words, the padding 0: occupancy_ema
      // and occupancy_mean read and write them a vec4 at a time.
      density_(ctx, VkDeviceSize(numWords()) * 32 * 4),
      bits_(ctx, VkDeviceSize(numWords()) * 4),
      fresh_(ctx, VkDeviceSize(numWords()) * 32 * 4),
      counter_(ctx, 4),
      mean_(ctx, 4),
      meanPartials_(ctx, VkDeviceSize(kOccupancyMeanGroups) * 4),
      wordSums_(ctx, VkDeviceSize(numWords()) * 4),
      points_(ctx, {gpu::shaders::occupancy_points, {gpu::Binding::Storage, gpu::Binding::Storage}, sizeof(PointsPush), {}}),
      splat_(ctx, {gpu::shaders::occupancy_splat, {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                   sizeof(SplatPush), {}}),
      ema_(ctx, {gpu::shaders::occupancy_ema, std::vector<gpu::Binding>(5, gpu::Binding::Storage), sizeof(EmaPush), {}}),
      meanKernel_(ctx, {gpu::shaders::occupancy_mean, std::vector<gpu::Binding>(4, gpu::Binding::Storage), sizeof(MeanPush), {}}),
      count_(ctx, {gpu::shaders::occupancy_count, {gpu::Binding::Storage, gpu::Binding::Storage}, sizeof(CountPush), {}}),
      unseen_(ctx, {gpu::shaders::occupancy_mark_unseen, {gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(UnseenPush), {}}) {
  density_.zero();
  bits_.zero();
  mean_.zero();
  wordSums_.zero();  // read only after an EMA wrote them; zeros should a recorded EMA never run
}

void OccupancyGrid::recordMarkAllOccupied(gpu::Recorder& rec) { rec.fill(bits_, 0xffffffffu); }

void OccupancyGrid::markUnseenEmpty(std::span<const Camera> cameras, const Aabb& box) {
  if (cameras.empty()) return;  // no camera to judge by: every cell stays as it is
  const auto views = gpu::Buffer::of(ctx_, core::viewBoundsOf(cameras));
  UnseenPush p{resolution_, cascades_, numCells_, uint32_t(cameras.size()), {}, {}};
  for (int k = 0; k < 3; ++k) {
    p.centre[k] = 0.5f * (box.min[k] + box.max[k]);
    p.halfExtent[k] = 0.5f * (box.max[k] - box.min[k]);
  }
  gpu::Recorder rec(ctx_);
  rec.begin();
  rec.dispatchFlat(unseen_, {views, density_}, p, numCells_, kUnseenLocal, "occupancy_mark_unseen");
  // bits = d > -1/2: every cell a camera sees (d >= 0) occupied, the unseen ones (d = -1) empty;
  // decay 1 and no fresh measurement leave the densities as they are.
  rec.fill(fresh_, 0u);
  recordEma(rec, 1.0f, -0.5f, false);
  rec.end();
  rec.submitAndWait();
}

void OccupancyGrid::recordAllCellPoints(gpu::Recorder& rec, uint32_t seed, const gpu::BufferRange& positions,
                                        const gpu::BufferRange& cells) {
  requireBytes("positions", positions, uint64_t(numCells_) * 16);
  requireBytes("cells", cells, uint64_t(numCells_) * 4);
  PointsPush p{resolution_, numCells_, seed, 0, cascades_};
  rec.dispatchFlat(points_, {positions, cells}, p, numCells_, kPointsLocal, "occupancy_points");
}

void OccupancyGrid::recordRandomCellPoints(gpu::Recorder& rec, uint32_t seed, uint32_t count,
                                           const gpu::BufferRange& positions, const gpu::BufferRange& cells) {
  requireBytes("positions", positions, uint64_t(count) * 16);
  requireBytes("cells", cells, uint64_t(count) * 4);
  PointsPush p{resolution_, count, seed, 1, cascades_};
  rec.dispatchFlat(points_, {positions, cells}, p, count, kPointsLocal, "occupancy_points");
}

float OccupancyGrid::decayFor(float decayPerQuarter, uint32_t measured, uint32_t cells) {
  const double share = cells ? std::min(1.0, 4.0 * double(measured) / double(cells)) : 1.0;
  return float(std::pow(double(decayPerQuarter), share));
}

void OccupancyGrid::recordUpdate(gpu::Recorder& rec, const Measured& measured, const Update& update) {
  const gpu::BufferRange &cells = measured.cells, &density = measured.density;
  const uint32_t count = measured.count, densityStride = measured.densityStride,
                 densityComponent = measured.densityComponent;
  const float decay = update.decay, threshold = update.threshold;
  const bool capAtMeanDensity = update.capAtMeanDensity;
  if (densityStride == 0 || densityComponent >= densityStride)
    throw Error("OccupancyGrid: density component " + std::to_string(densityComponent) + " of stride " +
                std::to_string(densityStride));
  if (!(decay >= 0.0f && decay <= 1.0f)) throw Error("OccupancyGrid: decay " + std::to_string(decay) + " is outside [0, 1]");
  if (!(threshold >= 0.0f && std::isfinite(threshold)))
    throw Error("OccupancyGrid: threshold " + std::to_string(threshold) + " must be finite and >= 0");
  requireBytes("cells", cells, uint64_t(count) * 4);
  requireBytes("density", density, uint64_t(count) * densityStride * 4);
  if (capAtMeanDensity) recordMeanDensity(rec);
  rec.fill(fresh_, 0u);
  SplatPush sp{count, densityStride, densityComponent};
  rec.dispatchFlat(splat_, {cells, density, fresh_}, sp, count, kSplatLocal, "occupancy_splat");
  recordEma(rec, decay, threshold, capAtMeanDensity);
}

void OccupancyGrid::recordEma(gpu::Recorder& rec, float decay, float threshold, bool capAtMean) {
  EmaPush ep{numCells_, decay, threshold, capAtMean ? 1u : 0u};
  rec.dispatchFlat(ema_, {density_, fresh_, bits_, mean_, wordSums_}, ep, numWords(), kEmaLocal, "occupancy_ema");
  wordSumsCurrent_ = true;
}

void OccupancyGrid::recordMeanDensity(gpu::Recorder& rec) {
  const uint32_t fromWordSums = wordSumsCurrent_ ? 1 : 0;
  const uint32_t terms = fromWordSums ? numWords() : (numCells_ + 3) / 4;  // sums of 32 cells, or vec4s of cells
  const uint32_t chunk = (terms + kOccupancyMeanGroups - 1) / kOccupancyMeanGroups;
  rec.dispatch(meanKernel_, {density_, meanPartials_, mean_, wordSums_}, MeanPush{numCells_, chunk, 0, fromWordSums},
               kOccupancyMeanGroups, 1, 1, "occupancy_mean_partials");
  rec.dispatch(meanKernel_, {density_, meanPartials_, mean_, wordSums_}, MeanPush{numCells_, chunk, 1, fromWordSums}, 1, 1,
               1, "occupancy_mean");
}

void OccupancyGrid::recordCountOccupied(gpu::Recorder& rec, gpu::Buffer& counter) {
  rec.fill(counter, 0u, 0, 4);
  CountPush p{numCells_};
  rec.dispatchFlat(count_, {bits_, counter}, p, (numWords() + kCountWords - 1) / kCountWords, kCountLocal,
                   "occupancy_count");
}

float OccupancyGrid::occupiedFraction() {
  gpu::Recorder rec(ctx_);
  rec.begin();
  recordCountOccupied(rec, counter_);
  rec.end();
  rec.submitAndWait();
  return float(double(counter_.download<uint32_t>(1)[0]) / numCells_);
}

OccupancyBits OccupancyGrid::hostBits() const {
  return {resolution_, cascades_, bits_.download<uint32_t>(numWords())};
}

std::vector<double> OccupancyGrid::occupiedFractionPerCascade() {
  const OccupancyBits bits = hostBits();
  const uint32_t perCascade = numCells_ / cascades_;
  std::vector<double> out(cascades_, 0.0);
  for (uint32_t i = 0; i < numCells_; ++i)
    if (bits.occupied(i)) out[i / perCascade] += 1.0;
  for (double& f : out) f /= perCascade;
  return out;
}

}  // namespace vknerf::nerf

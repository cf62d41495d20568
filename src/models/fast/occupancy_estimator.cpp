#include "models/fast/occupancy_estimator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/math/rng.h"
#include "models/fast/fast_choices.h"
#include "nerf/sampling/points.h"
#include "nerf/sampling/sample_layout.h"
#include "vknerf/error.h"

namespace vknerf::models {

namespace {

constexpr float kOccupancyDecay = 0.95f;       // instant-ngp's EMA factor per update of a quarter of the cells
constexpr uint32_t kMaxOccupancyPoints = 1u << 18;
// The most steps one sample stretched through a fog stands for (FastModel::stepOpacity): at 0.05 a
// fog at the occupancy threshold (1% a step) is crossed in steps of 5.
constexpr uint32_t kStretch = 16;

float stepOf(const FastModel& m, const Aabb& box, uint32_t marchSteps) {
  return nerf::RayMarcher::diagonal(nerf::RayMarcher::innerCube(box, m.cascades)) / float(marchSteps);
}

// Cascades march with cone steps from the inner cube's step dt up to the outermost cell's diagonal
// (or dt, for a render asking for coarser steps than that).
nerf::ConeSteps coneStepsFor(const FastModel& m, const Aabb& box, float dt) {
  if (m.cascades <= 1) return {};
  return {m.coneAngle, std::max(dt, nerf::RayMarcher::diagonal(box) / float(m.gridResolution)), m.stepOpacity, kStretch};
}

}  // namespace

OccupancyEstimator::OccupancyEstimator(Context& ctx, const FastModel& model, const Aabb& box, uint32_t rayCapacity,
                                       uint32_t sampleCapacity, uint32_t renderMarchSteps, bool training)
    : box_(box),
      updateInterval_(model.gridUpdateInterval),
      warmupSteps_(model.gridWarmupSteps),
      emptyOpacity_(occupancyThresholdOf(model)),
      dt_(stepOf(model, box, renderMarchSteps ? renderMarchSteps : model.marchSteps)),
      trainedDt_(stepOf(model, box, model.marchSteps)),
      cone_(coneStepsFor(model, box, dt_)),
      grid_(ctx, model.gridResolution, model.cascades),
      // A render's blocks give each ray room for all its samples: they march once, into slots.
      marcher_(ctx, rayCapacity, training ? 0 : sampleCapacity),
      sampleCapacity_(sampleCapacity),
      offsets_(gpu::Buffer::zeros(ctx, (VkDeviceSize(rayCapacity) + 1) * 4)),
      samples_(gpu::Buffer::zeros(ctx, VkDeviceSize(sampleCapacity) * nerf::kSampleBytes, "the marched samples")),
      sampleRay_(gpu::Buffer::zeros(ctx, VkDeviceSize(sampleCapacity) * 4, "the marched samples' ray ids")),
      totals_(gpu::Buffer::zeros(ctx, nerf::PackedLayout::kTotalsBytes)) {
  if (!(dt_ > 0) || !std::isfinite(dt_)) throw Error("fast model: the scene box is empty");
  if (training) {
    updatePoints_ = std::min(grid_.numCells(), kMaxOccupancyPoints);
    updatePositions_ = gpu::Buffer::zeros(ctx, VkDeviceSize(updatePoints_) * nerf::kPointBytes, "the occupancy update's points");
    updateDensity_ = gpu::Buffer::zeros(ctx, VkDeviceSize(updatePoints_) * 4, "the occupancy update's densities");
    updateCells_ = gpu::Buffer::zeros(ctx, VkDeviceSize(updatePoints_) * 4);
  }
  gpu::Recorder rec(ctx);
  rec.begin();
  grid_.recordMarkAllOccupied(rec);  // nothing is skipped until the field has been measured
  rec.end();
  rec.submitAndWait();
}

void OccupancyEstimator::recordMarch(gpu::Recorder& rec, const nerf::RaySpan& rays, uint32_t maxSamples, uint32_t seed,
                                     bool jitter, uint32_t group) {
  nerf::ConeSteps cone = cone_;
  if (const uint32_t span = candidateSpan(group); span > 1) {
    cone.stepOpacity = std::numeric_limits<float>::max();  // stretch through every occupied cell
    cone.stretch = span;
  }
  marcher_.record(rec, rays, grid_, box_, {dt_, maxSamples, seed, jitter, cone}, samples());
}

uint32_t OccupancyEstimator::candidateSpan(uint32_t group) const {
  return group > 1 && grid_.cascades() > 1 ? std::min(group, nerf::RayMarcher::kMaxStretch) : 1;
}

void OccupancyEstimator::recordCutToWholeRays(gpu::Recorder& rec, uint32_t rays, uint32_t rayAlign,
                                              const gpu::BufferRange& wholeRays) {
  marcher_.recordCutToWholeRays(rec, {rays, sampleCapacity_, rayAlign}, samples(), wholeRays);
}

void OccupancyEstimator::recordUpdateIfDue(gpu::Recorder& rec, uint32_t step, uint32_t runSeed, const DensityQuery& density) {
  if (!updateInterval_ || step % updateInterval_ != 0 || step == 0) return;
  const uint32_t seed = core::pcgHash(runSeed * 31u + step + 0x5bd1e995u);
  uint32_t count;
  if (step < warmupSteps_ && grid_.numCells() <= updatePoints_) {
    count = grid_.numCells();
    grid_.recordAllCellPoints(rec, seed, updatePositions_, updateCells_);
  } else {
    // After warm-up a quarter of the cells per update (with repetition) keeps up with the field.
    count = step < warmupSteps_ ? updatePoints_ : std::max(1u, updatePoints_ / 4);
    grid_.recordRandomCellPoints(rec, seed, count, updatePositions_, updateCells_);
  }
  // instant-ngp's threshold: the density at which one step is 1% opaque (FastModel::occupancyThreshold),
  // or the grid's mean density (before this update, computed on the device; a cell no camera sees counts as 0) when that is
  // lower, so that a young field whose densities are all small is not declared empty everywhere
  // (nothing would be sampled, and nothing learnt).
  const float threshold = nerf::OccupancyGrid::densityThreshold(emptyOpacity_, trainedDt_);
  density(rec, count, updatePositions_, updateDensity_);
  const float decay = nerf::OccupancyGrid::decayFor(kOccupancyDecay, count, grid_.numCells());
  grid_.recordUpdate(rec, {updateCells_, updateDensity_, count}, {decay, threshold, true});
}

void OccupancyEstimator::appendState(std::vector<StateArray>& out) {
  out.push_back({"occupancy.density", &grid_.density(), grid_.numCells(), false});
  // uint words, carried bit for bit through the float section
  out.push_back({"occupancy.bits", &grid_.bits(), grid_.numWords(), false, false});
}

void OccupancyEstimator::addStatistics(ModelStatistics& s) {
  s.occupiedFraction = grid_.occupiedFraction();
  s.occupiedFractionPerCascade = grid_.occupiedFractionPerCascade();
  if (grid_.cascades() != 1) return;
  // The box the occupied cells span: what the scene needs of the box it was given.
  auto bits = grid_.bits().download<uint32_t>(grid_.numWords());
  const uint32_t res = grid_.resolution();
  uint32_t lo[3] = {res, res, res}, hi[3] = {0, 0, 0};
  for (uint32_t i = 0; i < grid_.numCells(); ++i) {
    if (!((bits[i >> 5] >> (i & 31)) & 1u)) continue;
    const uint32_t c[3] = {i % res, (i / res) % res, i / (res * res)};
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k] + 1);
  }
  double boxFraction = 1;
  for (int k = 0; k < 3; ++k) boxFraction *= hi[k] > lo[k] ? double(hi[k] - lo[k]) / res : 0.0;
  s.occupiedBoxFraction = boxFraction;
}

}  // namespace vknerf::models

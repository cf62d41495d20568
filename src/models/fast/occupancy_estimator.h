#pragma once
// The fast model's sampler (nerfacc's OccGridEstimator): the occupancy grid over its cascades, the
// march that steps rays through its occupied cells into a packed batch of samples, and the grid's
// update schedule (update_every_n_steps): every FastModel::gridUpdateInterval steps the density at
// jittered points of the cells (every cell during the warm-up, then a quarter of them) is measured
// through the caller's density query and folded into the grid (EMA, threshold -> bits). Its grid is
// checkpoint state (a StatePart); the samples it marched are read by the field and the compositor.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/common/parameter_groups.h"
#include "nerf/occupancy/occupancy_grid.h"
#include "nerf/rays/rays.h"
#include "nerf/sampling/packed_samples.h"
#include "nerf/sampling/ray_marcher.h"
#include "vknerf/camera.h"
#include "vknerf/config.h"
#include "vknerf/model_statistics.h"

namespace vknerf::models {

// The density (sigma, activated) at `count` points (vec4, the box mapped onto [-1, 1]^3), written
// as one float per point.
using DensityQuery = std::function<void(gpu::Recorder& rec, uint32_t count, const gpu::BufferRange& positions,
                                        const gpu::BufferRange& density)>;

class OccupancyEstimator final : public StatePart {
 public:
  // `model`'s grid and march over `box`, for batches of up to rayCapacity rays and sampleCapacity
  // samples; renderMarchSteps: a render's steps per diagonal (0: the trained ones); training: with
  // the buffers of the update. Every cell starts occupied (nothing is skipped until the field has
  // been measured).
  OccupancyEstimator(Context& ctx, const FastModel& model, const Aabb& box, uint32_t rayCapacity, uint32_t sampleCapacity,
                     uint32_t renderMarchSteps, bool training);

  // Before training: the cells no training camera sees are empty for good (OccupancyGrid::markUnseenEmpty).
  void markUnseenEmpty(std::span<const Camera> cameras) { grid_.markUnseenEmpty(cameras, box_); }

  // The march of `rays` into samples() (at most maxSamples per ray; jittered starts from `seed`).
  // group > 1 (cascades only): each sample stands for up to `group` consecutive steps through
  // occupied cells, whatever their density (the proposal's candidates: a coarser march that still
  // skips exactly the empty cells the plain march skips).
  void recordMarch(gpu::Recorder& rec, const nerf::RaySpan& rays, uint32_t maxSamples, uint32_t seed, bool jitter,
                   uint32_t group = 1);
  // The most march steps one sample of recordMarch(..., group) stands for: group, capped at the
  // march's stretch, with cascades; 1 on one grid, which marches plain steps.
  uint32_t candidateSpan(uint32_t group) const;
  // After a march at the sample capacity: the batch cut on the device to the rays that fit it
  // whole (multiples of rayAlign), their count written to `wholeRays`.
  void recordCutToWholeRays(gpu::Recorder& rec, uint32_t rays, uint32_t rayAlign, const gpu::BufferRange& wholeRays);
  nerf::PackedSamples samples() const { return {offsets_, samples_, sampleRay_, totals_}; }
  const gpu::Buffer& offsets() const { return offsets_; }
  const gpu::Buffer& sampleRay() const { return sampleRay_; }
  const gpu::Buffer& marchedSamples() const { return samples_; }
  const gpu::Buffer& totals() const { return totals_; }

  // Training step `step`'s grid update when one is due (seed: the run's); none at step 0.
  void recordUpdateIfDue(gpu::Recorder& rec, uint32_t step, uint32_t seed, const DensityQuery& density);
  // The most points one update measures (the density query's rows).
  uint32_t maxUpdatePoints() const { return updatePoints_; }

  // The march's spacing: the smallest step now (a render may march finer) and in training (what
  // the occupancy threshold and the distortion loss's distances are taken in), and how steps grow
  // with distance (cascades only).
  float dt() const { return dt_; }
  float trainedDt() const { return trainedDt_; }
  const nerf::ConeSteps& cone() const { return cone_; }

  // "occupancy.density", "occupancy.bits" (uint words carried bit for bit through the float section).
  void appendState(std::vector<StateArray>& out) override;
  // Where a render samples at all: the grid's bits, read back.
  std::optional<nerf::OccupancyBits> occupiedCells() const { return grid_.hostBits(); }
  // The occupied fractions (per cascade) and, with one cascade, the box the occupied cells span.
  void addStatistics(ModelStatistics& s);

 private:
  Aabb box_;
  uint32_t updateInterval_, warmupSteps_;
  float emptyOpacity_;  // a cell is empty where one trained step through it is less opaque than this
  float dt_, trainedDt_;
  nerf::ConeSteps cone_;
  nerf::OccupancyGrid grid_;
  nerf::RayMarcher marcher_;
  uint32_t sampleCapacity_;
  // the packed batch (RayMarcher's layout)
  gpu::Buffer offsets_, samples_, sampleRay_, totals_;
  // training: the update's jittered points in cells and the density measured there
  uint32_t updatePoints_ = 0;
  gpu::Buffer updatePositions_, updateDensity_, updateCells_;
};

}  // namespace vknerf::models

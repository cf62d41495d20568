#pragma once
// The fast (instant-ngp style) pipeline: only what the scene needs.
//   rays -> march through the occupancy grid (packed samples, empty cells skipped) -> points
//        -> hash grid(x), SH(d) -> small MLP (trunc-exp density) -> composite (packed)
// and, when training, photometric loss -> composite backward -> MLP backward (dL/dfeatures)
// -> hash-grid backward -> Adam (MLP and table), with the occupancy grid re-measured every K steps.
// With FarField::Learned each ray's background is the learned far field in its direction
// (models/common/far_field.h), trained from the light the ray leaves behind the box.
// The number of samples a batch marches is known only on the device: a training step is recorded
// for the sample capacity, cut on the device to the whole rays and their samples, and submitted
// once; after its wait the host reads those counts (a few bytes, mapped) and adapts the next step's
// ray count to hold about FastModel::samplesPerBatch samples.
#include <memory>
#include <optional>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/common/appearance.h"
#include "models/common/camera_refinement.h"
#include "models/common/far_field.h"
#include "models/common/field_batch.h"
#include "models/common/ray_batch.h"
#include "models/common/trainable_parameters.h"
#include "models/field_pipeline.h"
#include "nerf/encoding/hash_encoding.h"
#include "nerf/encoding/sh_encoding.h"
#include "nerf/loss/photometric_loss.h"
#include "nerf/network/mlp.h"
#include "nerf/occupancy/occupancy_grid.h"
#include "nerf/render/composite.h"
#include "nerf/render/segment_accumulator.h"
#include "nerf/sampling/kept_rows.h"
#include "nerf/sampling/packed_points.h"
#include "nerf/sampling/ray_marcher.h"
#include "nerf/sampling/segment_rows.h"
#include "vknerf/config.h"

namespace vknerf::models {

nerf::HashGridConfig hashGridConfigFor(const FastModel& model);

class FastPipeline final : public FieldPipeline {
 public:
  FastPipeline(Context& ctx, const TrainConfig& config, const Aabb& box, uint32_t rayCapacity, bool training,
               const RenderSettings& overrides = {});

  uint32_t rayCapacity() const override { return rayCapacity_; }
  const gpu::Buffer& color() const override { return color_; }
  const gpu::Buffer& depth() const override { return depth_; }
  const gpu::Buffer& backgrounds() const override { return rays_.background(); }
  const gpu::Buffer& lossPartials() const override { return partials_; }
  void markUnseenEmpty(std::span<const Camera> cameras) override { grid_.markUnseenEmpty(cameras, box_); }
  void setTrainingCameras(uint32_t count) override;
  std::vector<std::array<float, 6>> cameraCorrections() override;
  std::vector<StateArray> state() override;

  FieldBatch& queryBatch() override { return field_; }
  void recordQuery(gpu::Recorder& rec, uint32_t count) override { recordFieldAt(rec, field_, count); }

  // A training step runs its forward in segments once the last step kept at most this fraction of
  // its marched samples (default kSegmentsBelowKept; 1: always, below 0: never).
  void segmentTrainingBelowKept(double fraction) { segmentsBelowKept_ = fraction; }
  std::optional<nerf::OccupancyBits> occupancyBits() const override { return grid_.hostBits(); }
  // Samples a render has shaded (and composited) since the pipeline was built: with segments, the
  // ones in front of where each ray became opaque (up to a segment's end).
  uint64_t renderedSamples() const { return renderedSamples_; }
  size_t parameterCount() const { return table_.count() + network_.count() + (farField_ ? farField_->parameterCount() : 0); }

 private:
  void doRecordRender(gpu::Recorder& rec, const ViewBlock& view, bool mayWait) override;
  void allocateTraining(Context& ctx);
  // A training step, one submission: the occupancy update when due, then the named steps below.
  uint32_t doRecordTrainStep(gpu::Recorder& rec, const TrainingData& data, nerf::OptimizerStep at) override;
  StepSize doCollectTrainStep(uint32_t slot) override;
  // R random training rays marched, the batch cut on the device to the rays that fit the sample capacity whole.
  nerf::RaySpan recordTrainingBatch(gpu::Recorder& rec, const TrainingData& data, uint32_t seed, uint32_t R);
  // Field, compositing and photometric loss over the batch; returns what the backward composites again.
  nerf::CompositeInputs recordTrainingForward(gpu::Recorder& rec, const TrainingData& data, const nerf::RaySpan& batch);
  // Compositor, far field, MLP and hash-grid backward; the cameras' gradient when they are refined.
  void recordTrainingBackward(gpu::Recorder& rec, const nerf::RaySpan& batch, const nerf::CompositeInputs& composite);
  // The position gradient of the samples the backward ran over (dPosition_, ray r's rows
  // [rowOffsets[r], rowOffsets[r + 1])), carried to the cameras that made the batch's rays.
  void recordCameraGradient(gpu::Recorder& rec, const nerf::RaySpan& batch, const gpu::BufferRange& rowOffsets);
  // After the step's wait: the rays and samples it trained on; sets the next step's ray count.
  void recordStepCounts(gpu::Recorder& rec, uint32_t R, gpu::Buffer& counts);
  // The uint the device writes: how many of the batch's rays fit the sample capacity whole.
  gpu::BufferRange wholeRayCount() const { return gpu::BufferRange(wholeRays_, 0, sizeof(uint32_t)); }
  ModelStatistics modelStatistics() override;

  // The buffers of a packed batch of samples (RayMarcher's layout), handed to the stages as one value.
  struct Packed {
    Packed(Context& ctx, uint32_t rays, uint32_t samples);
    nerf::PackedSamples view() const { return {offsets, samples, sampleRay, totals}; }
    gpu::Buffer offsets, samples, sampleRay, totals;
  };
  // Marches `rays` (a block of rays_) into marched_.
  void recordMarch(gpu::Recorder& rec, const nerf::RaySpan& rays, uint32_t maxSamples, uint32_t seed, bool jitter);
  // Field at marched_'s samples of `rays` (the block last marched): points, encodings, MLP, recorded
  // for the sample capacity and cut on the device to the march's total (shaders/gpu/row_limit.glsl);
  // `keep` keeps the activations for backward (training: each sample sees its own photo's
  // appearance vector, when the model has them; a render sees the render's vector). With early
  // termination a training forward runs in segments, over the samples the compositor will read.
  void recordField(gpu::Recorder& rec, const nerf::RaySpan& rays, bool keep);
  // The encodings and the MLP over marched_'s rows below `limit` (a uint on the device), or over
  // the rows `gather` lists (a training forward's segment, SegmentRows).
  void recordFieldRows(gpu::Recorder& rec, const gpu::BufferRange& limit, const std::optional<gpu::BufferRange>& gather,
                       const std::optional<nerf::RowBias>& colourBias, bool keep);
  // The bias the appearance embedding adds to the colour layer of the MLP's rows: each sample its
  // ray's photo's (training) or the render's one vector's; none without an embedding.
  std::optional<nerf::RowBias> recordAppearance(gpu::Recorder& rec, bool training);
  // What the compositor reads of marched_'s rays [first, first + count): their samples, the field
  // there and each ray's background from rays_ (`background` where a ray has none of its own).
  nerf::CompositeInputs compositeInputs(uint32_t first, uint32_t count, const std::array<float, 3>& background);
  // The field at the first `count` positions and directions of `f`, nothing kept for backward.
  void recordFieldAt(gpu::Recorder& rec, FieldBatch& f, uint32_t count);
  void recordOccupancyUpdate(gpu::Recorder& rec, uint32_t step);

  Context& ctx_;
  TrainConfig config_;
  FastModel model_;
  Aabb box_;
  uint32_t rayCapacity_, sampleCapacity_;
  bool training_;
  float dt_, trainedDt_;  // march step now, and in training (the occupancy threshold's): the smallest
  nerf::ConeSteps cone_;        // how steps grow with distance (cascades only)
  nerf::HashEncoding hash_;
  nerf::ShEncoding sh_;
  nerf::NerfMlp mlp_;
  TrainableParameters table_, network_;  // the hash grid's entries, the MLP's weights
  nerf::OccupancyGrid grid_;
  RayBatch rays_;
  nerf::RayMarcher marcher_;
  nerf::PackedSamplePoints points_;
  nerf::Compositor compositor_;
  std::optional<nerf::PhotometricLoss> loss_;
  std::optional<LearnedFarField> farField_;  // FarField::Learned: writes the rays' backgrounds
  std::optional<CameraRefinement> cameras_;  // FastModel::refineCameras, once the cameras are known
  std::optional<Appearance> appearance_;     // FastModel::appearanceDims, once the cameras are known
  std::optional<uint32_t> renderPhoto_;      // RenderSettings::appearancePhoto
  gpu::Buffer dColour_;                      // training with it: dL/d(colour pre-activation) per backward row
  gpu::Buffer dPosition_;                    // with it: dL/dp per backward row (vec4)

  // per ray
  gpu::Buffer color_, depth_, dColor_, zeroDepthGrad_, partials_;
  // Early termination (training): the samples each ray kept. When the batch fits one chunk of the
  // MLP (always, short of a huge sample budget), the backward runs over them packed (gatherBackward_);
  // else over every marched sample, with a zero gradient behind each ray's cut.
  std::optional<nerf::KeptRows> kept_;
  bool gatherBackward_ = false;
  // With it, the training forward runs in segments over the rows the compositor reads (SegmentRows).
  std::optional<nerf::SegmentRows> segmentRows_;
  // per sample
  Packed marched_;
  FieldBatch field_;
  gpu::Buffer weights_, dPos_;
  // host-readable, one per step in flight: rays, marched and kept samples of that step
  std::array<gpu::Buffer, kStepsInFlight> stepCounts_;
  gpu::Buffer wholeRays_;  // a training batch's rays that fit the sample capacity whole (device-written)
  nerf::SegmentAccumulator segments_;  // a render's rays, marched segment by segment
  float renderMinTransmittance_;  // where a render's ray stops (RenderSettings)
  uint64_t renderedSamples_ = 0;
  uint64_t marchedSamples_ = 0, keptSamples_ = 0, marchedRays_ = 0;
  // occupancy update (training): jittered points in cells, their encodings and the density there
  uint32_t occPoints_ = 0;
  gpu::Buffer occPositions_, occFeatures_, occDensity_, occCells_;

  // The adaptive ray count of the next step in each slot, set from the counts of the slot's last step.
  std::array<uint32_t, kStepsInFlight> raysFor_;
  double lastSamplesPerRay_ = 0;
  double lastKeptFraction_ = 1;  // of the last step's marched samples, those in front of the cut
  double segmentsBelowKept_;
  uint32_t lastRays_ = 0, lastSamples_ = 0;
};

}  // namespace vknerf::models

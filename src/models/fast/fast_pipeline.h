#pragma once
// The fast (instant-ngp style) pipeline: only what the scene needs.
//   rays -> OccupancyEstimator: march through the occupancy grid (packed samples, empty cells skipped)
//        -> points -> FastField: position encoding (hash grid), SH(d) -> small MLP (trunc-exp density)
//        -> composite (packed)
// and, when training, photometric loss -> composite backward -> field backward -> every registered
// part's optimizer step, with the occupancy grid re-measured on the estimator's schedule.
// With the proposal sampler (FastModel::sampler) the march's samples are candidates: a small
// proposal field is evaluated at them, and each ray's field samples are placed by inverse CDF of its weights
// (nerf::ProposalSampler); in training the proposal learns from the interlevel loss against the
// field's weights (nerf::InterlevelLoss), and a render marches each ray whole in one round.
// With FarField::Learned each ray's background is the learned far field in its direction
// (models/common/far_field.h), trained from the light the ray leaves behind the box. Camera
// refinement and the appearance embedding are step extensions (models/common/step_extension.h).
// The number of samples a batch marches is known only on the device: a training step is recorded
// for the sample capacity, cut on the device to the whole rays and their samples, and submitted
// once; after its wait the host reads those counts (a few bytes, mapped) and adapts the ray count of
// the step kStepsInFlight later to hold about FastModel::samplesPerBatch samples.
#include <array>
#include <memory>
#include <optional>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/common/appearance.h"
#include "models/common/camera_refinement.h"
#include "models/common/far_field.h"
#include "models/common/ray_batch.h"
#include "models/fast/adaptive_batch.h"
#include "models/fast/fast_field.h"
#include "models/fast/occupancy_estimator.h"
#include "models/field_pipeline.h"
#include "nerf/loss/photometric_loss.h"
#include "nerf/render/composite.h"
#include "nerf/render/segment_accumulator.h"
#include "nerf/sampling/interlevel_loss.h"
#include "nerf/sampling/kept_rows.h"
#include "nerf/sampling/packed_points.h"
#include "nerf/sampling/proposal_sampler.h"
#include "nerf/sampling/segment_rows.h"
#include "vknerf/config.h"

namespace vknerf::models {

class FastPipeline final : public FieldPipeline {
 public:
  FastPipeline(Context& ctx, const TrainConfig& config, const Aabb& box, uint32_t rayCapacity, bool training,
               const RenderSettings& overrides = {}, const TrainingPhotos& photos = {});

  RenderOutputs renderOutputs() const override { return {color_, depth_, rays_.background()}; }
  FieldBatch& queryBatch() override { return field_.batch(); }
  void recordQuery(gpu::Recorder& rec, uint32_t count) override;
  std::optional<nerf::OccupancyBits> sampledCells() const override { return estimator_.occupiedCells(); }

  // A training step runs its forward in segments once the last step kept at most this fraction of
  // its marched samples (default kSegmentsBelowKept; 1: always, below 0: never).
  void segmentTrainingBelowKept(double fraction) { segmentsBelowKept_ = fraction; }
  size_t parameterCount() const { return parts().parameterCount(); }

 private:
  void doRecordRender(gpu::Recorder& rec, const ViewBlock& view, bool mayWait) override;
  void allocateTraining(Context& ctx);
  void addExtensions(Context& ctx, const TrainingPhotos& photos, const RenderSettings& overrides);
  // A training step, one submission: the occupancy update when due, then the named steps below.
  uint32_t doRecordTrainStep(gpu::Recorder& rec, const TrainingData& data, nerf::OptimizerStep at) override;
  StepSize doCollectTrainStep(uint32_t slot) override;
  // R random training rays marched, the batch cut on the device to the rays that fit the sample capacity whole.
  // A training step's draws: its random stream, and how far the proposal's weights place its
  // samples (proposalAnneal; 1 without the proposal).
  struct StepDraws {
    uint32_t seed;
    float anneal;
  };
  nerf::RaySpan recordTrainingBatch(gpu::Recorder& rec, const TrainingData& data, StepDraws draws, uint32_t R);
  // The batch as the step extensions see it.
  StepBatch stepBatch(const nerf::RaySpan& batch);
  // Field, compositing and photometric loss over the batch; returns what the backward composites again.
  nerf::CompositeInputs recordTrainingForward(gpu::Recorder& rec, const TrainingData& data, const StepBatch& batch);
  // Compositor, far field and field backward, then the extensions' gradients.
  void recordTrainingBackward(gpu::Recorder& rec, const StepBatch& batch, const nerf::CompositeInputs& composite);
  // Within the step: the rays and samples it trained on, copied for the host (AdaptiveBatch).
  void recordStepCounts(gpu::Recorder& rec, uint32_t R, uint32_t slot);
  // The uint the device writes: how many of the batch's rays fit the sample capacity whole.
  gpu::BufferRange wholeRayCount() const { return gpu::BufferRange(wholeRays_, 0, sizeof(uint32_t)); }
  ModelStatistics modelStatistics() override;

  // The field at the estimator's samples of `rays` (the block last marched): points, then the
  // field, recorded for the sample capacity and cut on the device to the march's total
  // (shaders/gpu/row_limit.glsl). A training step (`batch`) keeps the activations for backward,
  // each sample with its own photo's colour bias, and runs in segments over the samples the
  // compositor will read once early termination keeps few of them; a render adds the render's bias.
  void recordField(gpu::Recorder& rec, const nerf::RaySpan& rays, const StepBatch* batch);
  // The colour layer's bias from the step extensions: a training batch's or a render's (none).
  std::optional<nerf::RowBias> recordColourBias(gpu::Recorder& rec, const StepBatch* batch);
  // The samples the field evaluates: the march's, or those the proposal placed on them.
  nerf::PackedSamples fieldSamples() const;
  // With the proposal: the proposal field at the march's samples of `rays`, then each ray's field
  // samples placed by its weights: in a training step (`step`) jittered by its draws and annealed,
  // its activations kept; in a render by the weights in full, with no jitter.
  void recordProposal(gpu::Recorder& rec, const nerf::RaySpan& rays, std::optional<StepDraws> step);
  // Training with the proposal: the interlevel loss against the field's weights (weights_), and the
  // proposal's backward.
  void recordProposalBackward(gpu::Recorder& rec, uint32_t R);
  // A render's rays a block: as many as the march's capacity holds at samplesPerRay each, in whole
  // multiples of kRayAlign (at least one), at most count.
  uint32_t renderBlock(uint32_t count, uint32_t samplesPerRay) const;
  // With the proposal: the most rays one batch of the field holds at their samples each.
  uint32_t proposalRays() const;
  // Where a render gathers the rays [first, first + count): their backgrounds, colours and depths.
  nerf::SegmentAccumulator::Gathered gatheredRays(uint32_t first, uint32_t count);
  // A waited render's round: submitted and waited for, its composited samples counted.
  void waitForRound(gpu::Recorder& rec);
  // A render with the proposal: each block of rays marched whole, the proposal's samples shaded.
  void recordProposalRender(gpu::Recorder& rec, uint32_t count, bool mayWait);
  // What the compositor reads of the marched rays [first, first + count): their samples, the field
  // there and each ray's background from rays_ (`background` where a ray has none of its own).
  nerf::CompositeInputs compositeInputs(uint32_t first, uint32_t count, const std::array<float, 3>& background);

  TrainConfig config_;
  FastModel model_;
  Aabb box_;
  uint32_t sampleCapacity_;  // the samples a march holds
  uint32_t fieldCapacity_;   // the samples the field evaluates at once: the march's or the proposal's
  bool training_;
  // Before the estimator: a batch of rays over one binding's limit names the rays, not the march.
  RayBatch rays_;
  OccupancyEstimator estimator_;
  FastField field_;
  nerf::PackedSamplePoints points_;
  nerf::Compositor compositor_;
  std::optional<nerf::PhotometricLoss> loss_;
  std::optional<LearnedFarField> farField_;  // FarField::Learned: writes the rays' backgrounds
  std::optional<CameraRefinement> cameras_;  // FastModel::refineCameras, training
  std::optional<Appearance> appearance_;     // FastModel::appearanceDims, once the photos are known
  // The proposal estimator (Sampler::Proposal): its field at the march's samples, the
  // sampler and the samples it places (packed), and in training the interlevel loss, its gradient
  // for the proposal's weights and each ray's value of it.
  std::optional<FastField> proposal_;
  std::optional<nerf::ProposalSampler> proposalSampler_;
  gpu::Buffer placedOffsets_, placedSamples_, placedSampleRay_, placedTotals_;
  std::optional<nerf::InterlevelLoss> interlevel_;
  gpu::Buffer proposalWeightGrads_, interlevelValues_;
  std::optional<uint32_t> interlevelTerm_;

  // per ray
  gpu::Buffer color_, depth_, dColor_, zeroDepthGrad_;
  // Training with the distortion loss: its term in the loss report, and each ray's value of the
  // loss terms the compositor's backward adds (vec4, nerf::rayLossColumn).
  std::optional<uint32_t> distortionTerm_;
  gpu::Buffer rayLossValues_;
  // Early termination (training): the samples each ray kept. When the batch fits one chunk of the
  // MLP (always, short of a huge sample budget), the backward runs over them packed (gatherBackward_);
  // else over every marched sample, with a zero gradient behind each ray's cut.
  std::optional<nerf::KeptRows> kept_;
  bool gatherBackward_ = false;
  // With it, the training forward runs in segments over the rows the compositor reads (SegmentRows).
  std::optional<nerf::SegmentRows> segmentRows_;
  // per sample
  gpu::Buffer weights_;
  std::optional<AdaptiveBatch> batch_;  // training: each step's rays, from the counts of the steps before
  gpu::Buffer wholeRays_;  // a training batch's rays that fit the sample capacity whole (device-written)
  nerf::SegmentAccumulator segments_;  // a render's rays, marched segment by segment
  float renderMinTransmittance_;  // where a render's ray stops (RenderSettings)
  double segmentsBelowKept_;
};

}  // namespace vknerf::models

#include "models/fast/fast_pipeline.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "models/fast/proposal_field.h"
#include "vknerf/error.h"

namespace vknerf::models {

namespace {

constexpr uint32_t kRayAlign = 64;             // sub-batches start at multiples of this (binding offsets)
// Training's early termination (instant-ngp's 1e-4): the cut a render makes by default, one choice.
constexpr float kMinTransmittance = RenderSettings{}.minTransmittance;
// A render's first segment per ray (SegmentAccumulator). Over three 800x800 orbit views of a model
// trained on the sample scene, first segments of 24, 32 and 48 samples shaded 10.3, 11.0 and 12.2
// million samples; 32 rendered fastest (24 needs more rounds, 48 shades more behind the surfaces).
constexpr uint32_t kFirstSegment = 32;

// A training forward's segments (SegmentRows): each ray's first 4 samples, then samples [4, 8),
// [8, 16) and the rest, of the rays still short of their cut; used once the last step kept at most
// half of its marched samples. Measured on the 800x800 object (docs/performance.md, "The training
// forward in segments"): late in training a ray marches about 11 samples and keeps about 3, and a
// step takes 10% less time; early, when rays keep 90% of theirs, segments cost 4% more.
constexpr std::array<uint32_t, 5> kTrainingSegments{0, 4, 8, 16, UINT32_MAX};
constexpr double kSegmentsBelowKept = 0.5;

// A render may march finer than training did (the per-ray sample cap follows) and place another
// count of samples by the proposal.
FastModel withOverrides(FastModel m, const RenderSettings& overrides) {
  if (overrides.marchSteps) m.maxSamplesPerRay = std::max(m.maxSamplesPerRay, overrides.marchSteps);
  // makeFieldPipeline checked that a proposal places the samples; the range is checked before any
  // capacity follows from it.
  if (overrides.proposalSamples > FastModel::kMaxProposalSamples)
    throw Error("render settings: proposalSamples must be at most " + std::to_string(FastModel::kMaxProposalSamples) +
                ", got " + std::to_string(overrides.proposalSamples));
  if (overrides.proposalSamples) m.proposalSamples = overrides.proposalSamples;
  return m;
}

// One cascade unless the configuration asks for more (0, "from the dataset", is resolved by the trainer).
FastModel checked(FastModel m, bool training) {
  if (m.marchSteps == 0 || m.maxSamplesPerRay == 0) throw Error("fast model: march steps and samples per ray must be > 0");
  if (m.gridResolution == 0) throw Error("fast model: the occupancy grid's resolution is left to the march steps (0); a Trainer sets it");
  if (training && m.samplesPerBatch == 0)
    throw Error("fast model: the samples per training step are left to the dataset (0); a Trainer sets them");
  m.cascades = std::max(m.cascades, 1u);
  return m;
}

// A capacity that always holds kRayAlign whole rays, so every sub-batch makes progress: twice a
// training step's budget, or 64 samples per ray of a render batch.
uint32_t sampleCapacityFor(const FastModel& m, uint32_t rayCapacity, bool training) {
  const uint64_t minimum = uint64_t(kRayAlign) * m.maxSamplesPerRay + kRayAlign;
  const uint64_t wanted = training ? 2ull * m.samplesPerBatch : uint64_t(rayCapacity) * 64;
  return uint32_t(std::min<uint64_t>(std::max(minimum, wanted), 1ull << 28));
}

// The rays a batch at the proposal's samples holds: a training step's as many as twice its sample
// budget gives them (the march's headroom; the step takes about half), a render block's as many as
// the march's capacity holds at the most samples a ray (those are its candidates). Sizing the field
// for every ray of the pipeline instead held five times the device memory (the cup at 32 samples:
// 848 MiB against 152).
uint32_t proposalRaysFor(const FastModel& m, uint32_t rayCapacity, uint32_t sampleCapacity, bool training) {
  const uint32_t perRay = training ? m.proposalSamples : m.maxSamplesPerRay;
  const uint32_t budget = training ? 2 * m.samplesPerBatch : sampleCapacity;
  return std::min(rayCapacity, std::max(kRayAlign, budget / perRay / kRayAlign * kRayAlign));
}

// The samples the field evaluates at once: the march's, or with the proposal its rays' samples.
uint32_t fieldCapacityFor(const FastModel& m, uint32_t rayCapacity, uint32_t sampleCapacity, bool training) {
  if (!m.usesProposal()) return sampleCapacity;
  const uint64_t rays = proposalRaysFor(m, rayCapacity, sampleCapacity, training);
  return uint32_t(std::min<uint64_t>(rays * m.proposalSamples, 1ull << 28));
}

// The uniform share of a proposal's sampling mass (nerfacto's histogram padding, 0.01).
constexpr float kProposalPadding = 0.01f;

// The proposal's kernels in a profile, apart from the field's (they share the network's and the
// encoding's kernels).
constexpr const char* kProposalLabel = "proposal: ";

}  // namespace

FastPipeline::FastPipeline(Context& ctx, const TrainConfig& config, const Aabb& box, uint32_t rayCapacity,
                           bool training, const RenderSettings& overrides, const TrainingPhotos& photos)
    : FieldPipeline(ctx, std::max(rayCapacity, kRayAlign), training),
      config_(config),
      model_(withOverrides(checked(config.fastModel(), training), overrides)),
      box_(box),
      sampleCapacity_(sampleCapacityFor(model_, this->rayCapacity(), training)),
      fieldCapacity_(fieldCapacityFor(model_, this->rayCapacity(), sampleCapacity_, training)),
      training_(training),
      // The per-photo gradients (camera refinement, appearance) are summed over each photo's run of rays.
      rays_(ctx, this->rayCapacity(), model_.nearDistance > 0 ? model_.nearDistance : kNearPlane,
            model_.refineCameras || model_.appearanceDims > 0),
      estimator_(ctx, model_, box, this->rayCapacity(), sampleCapacity_, overrides.marchSteps, training),
      field_(ctx, config, training, fieldCapacity_, estimator_.maxUpdatePoints(), hashGridPosition(ctx, config, training)),
      points_(ctx),
      compositor_(ctx),
      color_(gpu::Buffer::zeros(ctx, VkDeviceSize(this->rayCapacity()) * 16)),
      depth_(gpu::Buffer::zeros(ctx, VkDeviceSize(this->rayCapacity()) * 4)),
      weights_(gpu::Buffer::zeros(ctx, VkDeviceSize(fieldCapacity_) * 4, "the compositing weights")),
      wholeRays_(gpu::Buffer::zeros(ctx, 16)),
      segments_(ctx, this->rayCapacity()),
      renderMinTransmittance_(overrides.minTransmittance),
      segmentsBelowKept_(kSegmentsBelowKept) {
  if (!(renderMinTransmittance_ >= 0 && renderMinTransmittance_ < 1))
    throw Error("render settings: minTransmittance must be in [0, 1), got " + std::to_string(renderMinTransmittance_));
  if (model_.farField == FarField::Learned)
    farField_.emplace(ctx, this->rayCapacity(), config.seed, config.background,
                      training ? std::optional(tableAdamOf(config)) : std::nullopt,
                      training ? std::optional(adamConfigOf(config)) : std::nullopt);
  if (model_.usesProposal()) {
    const TrainConfig proposalConfig = proposalConfigOf(config);
    proposal_.emplace(ctx, proposalConfig, training, sampleCapacity_, 0, hashGridPosition(ctx, proposalConfig, training),
                      kProposalStateName);
    proposalSampler_.emplace(ctx, this->rayCapacity());
    placedOffsets_ = gpu::Buffer::zeros(ctx, (VkDeviceSize(this->rayCapacity()) + 1) * 4, "the proposal's offsets");
    placedSamples_ = gpu::Buffer::zeros(ctx, VkDeviceSize(fieldCapacity_) * nerf::kSampleBytes, "the proposal's samples");
    placedSampleRay_ = gpu::Buffer::zeros(ctx, VkDeviceSize(fieldCapacity_) * 4, "the proposal's sample rays");
    placedTotals_ = gpu::Buffer::zeros(ctx, nerf::PackedLayout::kTotalsBytes, "the proposal's totals");
  }
  if (training) allocateTraining(ctx);
  // The model's state, in checkpoint order.
  parts().add(field_.encodingParameters(), ParameterRole::Encoding);
  parts().add(field_.networkParameters(), ParameterRole::Network);
  addExtensions(ctx, photos, overrides);
  if (farField_) parts().add(*farField_);
  parts().addState(estimator_);
  if (proposal_) {
    parts().add(proposal_->encodingParameters(), ParameterRole::Encoding);
    parts().add(proposal_->networkParameters(), ParameterRole::Network);
  }
  if (training && !photos.cameras.empty()) estimator_.markUnseenEmpty(photos.cameras);
}

// Camera refinement (training) and the appearance embedding, once the training photos are known
// (a loaded model: their count, from its checkpoint).
void FastPipeline::addExtensions(Context& ctx, const TrainingPhotos& photos, const RenderSettings& overrides) {
  if (training_ && model_.refineCameras && photos.count) {
    CameraRefinementSettings settings;
    settings.adam = adamConfigOf(config_, model_.cameraLearningRate / config_.learningRate);
    settings.penalty = model_.cameraPenalty;
    addExtension(cameras_.emplace(ctx, photos.count, fieldCapacity_, settings, report()));
  }
  if (model_.appearanceDims && photos.count) {
    // W_a starts as the colour layer's weights would with the vector among its inputs.
    const core::DenseShape& colour = field_.mlp().shape().colour();
    const AppearanceInit init{config_.seed, float(1.0 / std::sqrt(double(colour.ka + colour.kb + model_.appearanceDims)))};
    addExtension(appearance_.emplace(ctx, photos.count, model_.appearanceDims, colour.n4(), init,
                                     training_ ? std::optional(adamConfigOf(config_)) : std::nullopt,
                                     overrides.appearancePhoto, training_ ? fieldCapacity_ : 0));
  }
}

// The loss, gradients and early termination buffers of a training pipeline.
void FastPipeline::allocateTraining(Context& ctx) {
  loss_.emplace(ctx);
  dColor_ = gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity()) * 16);
  zeroDepthGrad_ = gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity()) * 4);
  if (model_.distortionLoss > 0) {
    distortionTerm_ = report().addTerm(LossReport::row("distortion_loss"), true);
    rayLossValues_ = gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity()) * 4 * nerf::kRayLossColumns, "the rays' loss terms");
  }
  // With the proposal a step's rays are bounded by the field's capacity at their samples each.
  batch_.emplace(ctx, proposal_ ? proposalRays() : rayCapacity(), kRayAlign, model_.samplesPerBatch);
  if (model_.earlyTermination) {
    kept_.emplace(ctx, rayCapacity(), fieldCapacity_);
    gatherBackward_ = fieldCapacity_ <= field_.mlp().chunkRows();
    // The proposal's few samples a ray lie where its weight does: segments would only add dispatches.
    if (gatherBackward_ && !proposal_) segmentRows_.emplace(ctx, fieldCapacity_);
  }
  if (proposal_) {
    interlevel_.emplace(ctx);
    interlevelTerm_ = report().addTerm(LossReport::row("proposal_loss"), true);
    proposalWeightGrads_ = gpu::Buffer::zeros(ctx, VkDeviceSize(sampleCapacity_) * 4, "the proposal's weight gradients");
    interlevelValues_ = gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity()) * 4, "the rays' interlevel losses");
  }
}

void FastPipeline::recordField(gpu::Recorder& rec, const nerf::RaySpan& rays, const StepBatch* batch) {
  FieldBatch& f = field_.batch();
  const nerf::PackedSamples samples = fieldSamples();
  // The proposal's sampler wrote its samples' field inputs with them.
  if (!proposal_) points_.record(rec, fieldCapacity_, rays.range, samples, box_, {f.positions, f.directions});
  const std::optional<nerf::RowBias> colourBias = recordColourBias(rec, batch);
  const bool keep = batch != nullptr;
  // A training step runs in segments, the field over the rows the compositor will read, once the
  // last step kept few of its marched samples; while rays keep most of theirs (early in training),
  // segments would only add dispatches.
  if (!keep || !segmentRows_ || batch_->lastKeptFraction() > segmentsBelowKept_)
    return field_.recordForward(rec, {fieldCapacity_, samples.total(), std::nullopt, colourBias}, keep);
  const float maxDepth = nerf::Compositor::maxOpticalDepth(kMinTransmittance);
  for (size_t s = 0; s + 1 < kTrainingSegments.size(); ++s) {
    segmentRows_->record(rec, rays.count, samples, gpu::BufferRange(f.field), maxDepth, kTrainingSegments[s],
                         kTrainingSegments[s + 1]);
    field_.recordForward(rec, {fieldCapacity_, segmentRows_->count(), gpu::BufferRange(segmentRows_->rows()), colourBias},
                         true);
  }
}

std::optional<nerf::RowBias> FastPipeline::recordColourBias(gpu::Recorder& rec, const StepBatch* batch) {
  if (model_.appearanceDims && !appearance_)
    throw Error("fast model: model.appearance_dims is " + std::to_string(model_.appearanceDims) +
                ", but the number of training photos (whose vectors it learns) was never given");
  std::optional<nerf::RowBias> bias;
  for (StepExtension* e : extensions())
    if (auto b = e->recordColourBias(rec, batch)) {
      if (bias) throw Error("fast model: two step extensions bias the colour layer; it takes one");
      bias = b;
    }
  return bias;
}

void FastPipeline::recordQuery(gpu::Recorder& rec, uint32_t count) {
  field_.recordForward(rec, {count, std::nullopt, std::nullopt, recordColourBias(rec, nullptr)}, false);
}

nerf::CompositeInputs FastPipeline::compositeInputs(uint32_t first, uint32_t count, const std::array<float, 3>& background) {
  nerf::CompositeInputs in = nerf::CompositeInputs::packed(count, fieldSamples(), field_.batch().field);
  in.background = background;
  in.perRayBackground = rays_.backgrounds(first, count);
  return in;
}

void FastPipeline::doRecordRender(gpu::Recorder& rec, const ViewBlock& view, bool mayWait) {
  const uint32_t count = view.count;
  if (count > rayCapacity())
    throw Error("fast model: render block of " + std::to_string(count) + " rays over capacity " + std::to_string(rayCapacity()));
  if (count == 0) return;
  rays_.recordView(rec, view, box_);
  if (farField_) farField_->recordForward(rec, count, rays_.rays(), rays_.background(), false);
  if (proposal_) return recordProposalRender(rec, count, mayWait);
  // A tile marched in segments, each ray stopped where it has turned opaque (SegmentAccumulator):
  // a first segment of kFirstSegment samples, then the rest of the model's samples per ray as the
  // capacity holds them for the rays still live (not yet opaque, their march not done). With the
  // host's waits (mayWait), the host reads after each segment how many rays are live, and a block
  // holds as many rays as the capacity gives kFirstSegment samples each (the whole tile when the
  // pipeline was built for rendering). Recorded into a caller's command buffer (no read-back), a
  // block holds as many rays as the capacity gives the model's samples per ray each, so that the
  // second segment marches all the rest: every ray gets the samples a waited render gives it, and
  // the two draw the same image (the ended rays march none; the field's kernels are recorded for the
  // capacity and skip the rows past the device's sample total, shaders/gpu/row_limit.glsl). A block
  // of count / capacity samples each would cut long rays short: a trainer's small capacity drew
  // another image than the saved model's render.
  const uint32_t most = model_.maxSamplesPerRay;
  const uint32_t perRay = mayWait ? kFirstSegment : most;
  const uint32_t block = renderBlock(count, perRay);
  for (uint32_t done = 0; done < count; done += block) {
    const uint32_t n = std::min(block, count - done);
    const nerf::RaySpan rays = rays_.rays(done, n);
    const nerf::SegmentAccumulator::Gathered gathered = gatheredRays(done, n);
    for (uint32_t marched = 0, live = n; live > 0 && marched < most;) {
      const uint32_t cap = std::min({std::max(1u, sampleCapacity_ / live), marched == 0 ? kFirstSegment : most,
                                     most - marched});
      const bool first = marched == 0, last = marched + cap >= most;
      if (mayWait) segments_.recordResetCounts(rec);
      estimator_.recordMarch(rec, rays, cap, 0, false);
      recordField(rec, rays, nullptr);
      compositor_.recordForward(rec, nerf::CompositeInputs::packed(n, estimator_.samples(), field_.batch().field),
                                {segments_.segmentColor(), segments_.segmentDepth(), weights_});
      segments_.record(rec, {cap, first, last, renderMinTransmittance_}, rays, estimator_.samples(), gathered);
      marched += cap;
      if (!mayWait) continue;
      waitForRound(rec);
      live = segments_.active();
    }
  }
}

uint32_t FastPipeline::doRecordTrainStep(gpu::Recorder& rec, const TrainingData& data, nerf::OptimizerStep at) {
  if (!training_) throw Error("fast model: pipeline was not built for training");
  const uint32_t step = at.step;
  const uint32_t seed = stepSeed(config_, step);
  estimator_.recordUpdateIfDue(rec, step, config_.seed,
                               [this](gpu::Recorder& r, uint32_t n, const gpu::BufferRange& positions,
                                      const gpu::BufferRange& density) { field_.recordDensity(r, n, positions, density); });
  // The step's rays come from the cameras as the extensions give them (camera refinement: as
  // corrected so far).
  TrainingData cameras = data;
  for (StepExtension* e : extensions()) cameras.cameras = &e->recordCameras(rec, cameras);
  const uint32_t slot = slotOf(step);
  const float anneal = proposal_ ? proposalAnneal(model_, step) : 1.0f;
  const StepBatch batch = stepBatch(recordTrainingBatch(rec, cameras, {seed, anneal}, batch_->rays(slot)));
  const nerf::CompositeInputs composite = recordTrainingForward(rec, cameras, batch);
  recordTrainingBackward(rec, batch, composite);
  parts().recordOptimizerSteps(rec, at);
  recordStepCounts(rec, batch.rays.count, slot);
  return batch.rays.count;
}

nerf::RaySpan FastPipeline::recordTrainingBatch(gpu::Recorder& rec, const TrainingData& data, StepDraws draws,
                                                uint32_t R) {
  const uint32_t seed = draws.seed;
  rays_.recordTraining(rec, data, seed, R, box_, config_);
  if (farField_) farField_->recordForward(rec, R, rays_.rays(), rays_.background(), true);
  const nerf::RaySpan batch = rays_.rays(0, R);
  estimator_.recordMarch(rec, batch, model_.maxSamplesPerRay, seed, true, proposal_ ? model_.proposalStride : 1);
  // The batch's size stays on the device: the rays that fit the sample capacity whole, and their
  // sample total (the march's totals, rewritten); every later kernel is recorded for the capacity
  // and cut to those counts (shaders/gpu/row_limit.glsl), so the step is one submission.
  estimator_.recordCutToWholeRays(rec, R, kRayAlign, wholeRayCount());
  if (proposal_) recordProposal(rec, batch, draws);
  return batch;
}

StepBatch FastPipeline::stepBatch(const nerf::RaySpan& rays) {
  // The backward runs over the kept samples packed (their offsets) or over every marched one.
  const nerf::PackedSamples samples = fieldSamples();
  const gpu::BufferRange rowOffsets = gatherBackward_ ? gpu::BufferRange(kept_->offsets()) : samples.offsets;
  return {rays, rays_.pixelIds(), samples.sampleRay, samples.offsets, samples.samples, rowOffsets, wholeRayCount(), box_};
}

nerf::CompositeInputs FastPipeline::recordTrainingForward(gpu::Recorder& rec, const TrainingData& data,
                                                          const StepBatch& batch) {
  // The field forward with activations kept, in segments over the samples in front of each ray's
  // cut (SegmentRows). The compositor stops each ray where the transmittance falls below 1e-4
  // (instant-ngp's early termination) and gives the samples behind that zero gradient, so the step
  // needs no separate pass (the field without gradients, then a compacted copy of the kept samples)
  // and never evaluates a sample twice; the backward then runs over the kept samples alone, reading
  // the forward's rows through their packed index (KeptRows).
  // The rays past the whole ones have no samples: the loss neither counts them nor gives them a gradient.
  const uint32_t R = batch.rays.count;
  nerf::CompositeInputs composite = compositeInputs(0, R, config_.background);
  if (model_.earlyTermination) composite.maxOpticalDepth = nerf::Compositor::maxOpticalDepth(kMinTransmittance);
  nerf::CompositeOutputs composited{gpu::rowsOf(color_, nerf::kColorBytes, 0, R), gpu::rowsOf(depth_, nerf::kDepthBytes, 0, R),
                                    weights_};
  if (kept_) composited.keptCounts = gpu::rowsOf(kept_->counts(), sizeof(uint32_t), 0, R);
  recordField(rec, batch.rays, &batch);
  compositor_.recordForward(rec, composite, composited);
  loss_->record(rec, {R, color_, rays_.pixelIds(), rays_.background(), wholeRayCount()},
                {data.pixels, *data.cameras}, {dColor_, report().photometricPartials()});
  return composite;
}

void FastPipeline::recordTrainingBackward(gpu::Recorder& rec, const StepBatch& batch, const nerf::CompositeInputs& composite) {
  const uint32_t R = batch.rays.count;
  FieldBatch& f = field_.batch();
  // The distortion loss, a mean over the batch's rays like the photometric loss (over the R rays
  // recorded: the rays past the device's cut have no samples, so they add nothing), its distances
  // even in the march's steps.
  const float dt = estimator_.dt();
  const nerf::DistortionLoss distortion{model_.distortionLoss / float(R), estimator_.cone().coneAngle, dt,
                                        std::max(dt, estimator_.cone().dtMax), batch.rays.range,
                                        model_.distortionFarField};
  nerf::CompositeGradients gradients{dColor_, zeroDepthGrad_, f.dField, {distortion}};
  if (distortionTerm_) gradients.termValues = gpu::BufferRange(rayLossValues_);
  compositor_.recordBackward(rec, composite, gradients);
  if (distortionTerm_)
    report().recordTerm(rec, *distortionTerm_,
                            {rayLossValues_, R, nerf::kRayLossColumns, nerf::rayLossColumn(distortion)});
  if (farField_) farField_->recordBackward(rec, R, *composite.perRayBackground, color_, dColor_);
  // With the kept samples packed, the backward runs over them alone: the MLP's reads the forward's
  // rows through their index, the encoding's reads the kept positions beside the packed encoding
  // gradients. Else it runs over every marched sample.
  FieldBackwardRows rows{fieldCapacity_, gpu::BufferRange(f.positions), fieldSamples().total(), std::nullopt};
  if (gatherBackward_) {
    kept_->record(rec, R, fieldSamples().offsets, f.positions);
    rows.positions = kept_->positions(), rows.limit = kept_->total(), rows.gather = kept_->rows();
  }
  FieldGradientTargets targets;
  for (StepExtension* e : extensions()) e->requestGradients(targets);
  field_.recordBackward(rec, rows, targets);
  for (StepExtension* e : extensions()) e->recordGradient(rec, batch);
  if (proposal_) recordProposalBackward(rec, R);
}

uint32_t FastPipeline::renderBlock(uint32_t count, uint32_t samplesPerRay) const {
  return std::min(count, std::max(kRayAlign, sampleCapacity_ / samplesPerRay / kRayAlign * kRayAlign));
}

uint32_t FastPipeline::proposalRays() const { return fieldCapacity_ / model_.proposalSamples; }

nerf::SegmentAccumulator::Gathered FastPipeline::gatheredRays(uint32_t first, uint32_t count) {
  return {rays_.backgrounds(first, count), gpu::rowsOf(color_, nerf::kColorBytes, first, count),
          gpu::rowsOf(depth_, nerf::kDepthBytes, first, count)};
}

void FastPipeline::waitForRound(gpu::Recorder& rec) {
  rec.end();
  rec.submitAndWait();
  rec.begin();
  countRenderedSamples(segments_.samples());
}

nerf::PackedSamples FastPipeline::fieldSamples() const {
  if (!proposal_) return estimator_.samples();
  return {placedOffsets_, placedSamples_, placedSampleRay_, placedTotals_};
}

void FastPipeline::recordProposal(gpu::Recorder& rec, const nerf::RaySpan& rays, std::optional<StepDraws> step) {
  const gpu::Recorder::LabelScope label(rec, kProposalLabel);
  const bool training = step.has_value();
  const uint32_t seed = training ? step->seed : 0;
  FieldBatch& p = proposal_->batch();
  const nerf::PackedSamples candidates = estimator_.samples();
  points_.record(rec, sampleCapacity_, rays.range, candidates, box_, {p.positions, p.directions}, true);
  // The proposal's densities alone are read and trained (nerfacto's proposal has no colour): its
  // colour layer and head take no gradient, and are neither run nor differentiated.
  proposal_->recordForward(rec, {sampleCapacity_, candidates.total(), std::nullopt, std::nullopt, true}, training);
  // The placement's jitter draws from its own stream: the march's draws are keyed by the same seed.
  const nerf::ProposalSampler::Draws draws{model_.proposalSamples, {seed ^ 0x9e3779b9u, training}, kProposalPadding,
                                           training ? step->anneal : 1.0f,
                                           estimator_.candidateSpan(model_.proposalStride)};
  FieldBatch& f = field_.batch();
  proposalSampler_->record(rec, rays.count, {candidates.offsets, candidates.samples, p.field}, draws, fieldCapacity_,
                           fieldSamples(), nerf::ProposalSampler::FieldInputs{rays.range, box_, {f.positions, f.directions}});
}

void FastPipeline::recordProposalBackward(gpu::Recorder& rec, uint32_t R) {
  const gpu::Recorder::LabelScope label(rec, kProposalLabel);
  FieldBatch& p = proposal_->batch();
  const nerf::PackedSamples candidates = estimator_.samples();
  // A mean over the batch's rays, as the photometric loss.
  const nerf::InterlevelLoss::Terms terms{model_.proposalLoss / float(R)};
  interlevel_->record(rec, R, {candidates.offsets, candidates.samples, p.field}, fieldSamples(), weights_, terms,
                      {proposalWeightGrads_, p.dField, interlevelValues_});
  report().recordTerm(rec, *interlevelTerm_, {interlevelValues_, R, 1, 0});
  proposal_->recordBackward(rec, {sampleCapacity_, gpu::BufferRange(p.positions), candidates.total(), std::nullopt, true},
                            {});
}

void FastPipeline::recordProposalRender(gpu::Recorder& rec, uint32_t count, bool mayWait) {
  // Every ray's candidates at once (the proposal's CDF spans the whole ray): a block holds as many
  // rays as the march's capacity holds at the most samples a ray.
  const uint32_t most = model_.maxSamplesPerRay;
  const uint32_t block = std::min(renderBlock(count, most), proposalRays());
  for (uint32_t done = 0; done < count; done += block) {
    const uint32_t n = std::min(block, count - done);
    const nerf::RaySpan rays = rays_.rays(done, n);
    const nerf::SegmentAccumulator::Gathered gathered = gatheredRays(done, n);
    if (mayWait) segments_.recordResetCounts(rec);
    estimator_.recordMarch(rec, rays, most, 0, false, model_.proposalStride);
    recordProposal(rec, rays, std::nullopt);
    recordField(rec, rays, nullptr);
    compositor_.recordForward(rec, nerf::CompositeInputs::packed(n, fieldSamples(), field_.batch().field),
                              {segments_.segmentColor(), segments_.segmentDepth(), weights_});
    segments_.record(rec, {model_.proposalSamples, true, true, renderMinTransmittance_}, rays, fieldSamples(), gathered);
    if (mayWait) waitForRound(rec);
  }
}

void FastPipeline::recordStepCounts(gpu::Recorder& rec, uint32_t R, uint32_t slot) {
  // The per-ray kept counts are summed on the device, not read back (up to 1 MB a step).
  const gpu::Buffer* kept = nullptr;
  if (model_.earlyTermination) {
    if (!gatherBackward_) kept_->recordTotal(rec, R);  // else the backward's packing made it
    kept = &kept_->totals();
  }
  // With the proposal a step's cost is the field's samples, the ones it placed: the rays adapt to those.
  batch_->recordCopy(rec, slot, {wholeRays_, proposal_ ? placedTotals_ : estimator_.totals(), kept});
}

FieldPipeline::StepSize FastPipeline::doCollectTrainStep(uint32_t slot) { return batch_->collect(slot); }

ModelStatistics FastPipeline::modelStatistics() {
  ModelStatistics s;
  s.mlpParameters = parts().parameterCount(ParameterRole::Network);
  s.encodingParameters = parts().parameterCount(ParameterRole::Encoding);
  estimator_.addStatistics(s);
  if (batch_)
    batch_->addStatistics(s);
  else
    s.keptByEarlyTermination = 1.0;  // a render pipeline has trained on nothing
  return s;
}

}  // namespace vknerf::models

#include "models/fast/fast_pipeline.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "nerf/sampling/points.h"
#include "core/math/rng.h"
#include "vknerf/error.h"

namespace vknerf::models {

namespace {

constexpr float kOccupancyDecay = 0.95f;       // instant-ngp's EMA factor per update of a quarter of the cells
constexpr float kOccupancyThickness = 0.01f;   // a cell is empty when one step through it is < 1% opaque
constexpr uint32_t kMaxOccupancyPoints = 1u << 18;
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

// A render may march finer than training did; the per-ray sample cap follows.
FastModel withOverrides(FastModel m, const RenderSettings& overrides) {
  if (overrides.marchSteps) m.maxSamplesPerRay = std::max(m.maxSamplesPerRay, overrides.marchSteps);
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

// Cascades march with cone steps from the inner cube's step dt up to the outermost cell's diagonal
// (or dt, for a render asking for coarser steps than that).
nerf::ConeSteps coneStepsFor(const FastModel& m, const Aabb& box, float dt) {
  if (m.cascades <= 1) return {};
  return {m.coneAngle, std::max(dt, nerf::RayMarcher::diagonal(box) / float(m.gridResolution))};
}

// A capacity that always holds kRayAlign whole rays, so every sub-batch makes progress: twice a
// training step's budget, or 64 samples per ray of a render batch.
uint32_t sampleCapacityFor(const FastModel& m, uint32_t rayCapacity, bool training) {
  const uint64_t minimum = uint64_t(kRayAlign) * m.maxSamplesPerRay + kRayAlign;
  const uint64_t wanted = training ? 2ull * m.samplesPerBatch : uint64_t(rayCapacity) * 64;
  return uint32_t(std::min<uint64_t>(std::max(minimum, wanted), 1ull << 28));
}

// A training pipeline runs its forward with the activations kept layer by layer (MlpTuning::fused);
// its occupancy update needs only the density (NerfMlp::recordDensity: the same trunk kernels and
// a small sigma kernel), so no fused inference kernel is compiled for it (~20 s on a fresh lavapipe).
nerf::MlpTuning mlpTuningFor(const Context& ctx, bool training) {
  nerf::MlpTuning t = nerf::MlpTuning::forDevice(ctx);
  if (training && !(t.fused & 2u)) t.fused = 0;
  return t;
}

// Every table entry takes an Adam step, also one no sample touched (its momentum carries it on).
// instant-ngp skips those (AdamConfig::skipZeroGradientsFrom) to save time where the gradients are
// sparse; at these tables (2^15 entries a level, ~16k samples a step) they are not: the skip saved
// about 1 ms of a ~65 ms step, and held-out PSNR in equal time was the same or better without it
// (docs/performance.md: +0.5 dB on the sample scene at 60 s and on an 800x800 object scene at 120 s).
nerf::AdamConfig tableAdamOf(const TrainConfig& config) {
  return adamConfigOf(config, config.fastModel().hashLearningRateScale);
}

// The field's table: the dense step while a step touches much of each level's slot, and the skip
// of the entries a step did not touch once a slot holds more than kDenseEntriesPerSample entries per
// sample a step marches (their zero gradients are read, nothing else), so that Adam's cost follows
// the touched entries and not the table's size (docs/performance.md, "Adam on large tables"). Every
// level alike: a coarse level's few entries are all touched every step either way, and the unused
// part of its slot (past its (res + 1)^3 vertices) would cost the dense step as much as a used one.
constexpr uint64_t kDenseEntriesPerSample = 4;
nerf::AdamConfig fieldTableAdamOf(const TrainConfig& config, const nerf::HashGridConfig& grid) {
  nerf::AdamConfig a = tableAdamOf(config);
  if ((uint64_t(1) << grid.log2TableSize) > kDenseEntriesPerSample * config.fastModel().samplesPerBatch)
    a.skipZeroGradientsFrom = 0;
  return a;
}

}  // namespace

nerf::HashGridConfig hashGridConfigFor(const FastModel& m) {
  if (m.hashLog2Size == 0 || m.hashGrowth == 0)
    throw Error("fast model: the hash table size or finest resolution is left to the dataset (0); a Trainer sets it");
  nerf::HashGridConfig c;
  c.levels = m.hashLevels;
  c.featuresPerLevel = m.hashFeatures;
  c.log2TableSize = m.hashLog2Size;
  c.baseResolution = m.hashBaseResolution;
  c.growthFactor = m.hashGrowth;
  return c;
}

FastPipeline::Packed::Packed(Context& ctx, uint32_t rays, uint32_t samples)
    : offsets(gpu::Buffer::zeros(ctx, (VkDeviceSize(rays) + 1) * 4)),
      samples(gpu::Buffer::zeros(ctx, VkDeviceSize(samples) * nerf::kSampleBytes, "the marched samples")),
      sampleRay(gpu::Buffer::zeros(ctx, VkDeviceSize(samples) * 4, "the marched samples' ray ids")),
      totals(gpu::Buffer::zeros(ctx, nerf::PackedLayout::kTotalsBytes)) {}

FastPipeline::FastPipeline(Context& ctx, const TrainConfig& config, const Aabb& box, uint32_t rayCapacity,
                           bool training, const RenderSettings& overrides)
    : ctx_(ctx),
      config_(config),
      model_(withOverrides(checked(config.fastModel(), training), overrides)),
      box_(box),
      rayCapacity_(std::max(rayCapacity, kRayAlign)),
      sampleCapacity_(sampleCapacityFor(model_, rayCapacity_, training)),
      training_(training),
      dt_(nerf::RayMarcher::diagonal(nerf::RayMarcher::innerCube(box, model_.cascades)) /
          float(overrides.marchSteps ? overrides.marchSteps : model_.marchSteps)),
      trainedDt_(nerf::RayMarcher::diagonal(nerf::RayMarcher::innerCube(box, model_.cascades)) / float(model_.marchSteps)),
      cone_(coneStepsFor(model_, box, dt_)),
      hash_(ctx, hashGridConfigFor(model_)),
      sh_(ctx, model_.shDegree),
      mlp_(ctx, nerf::MlpConfig{.depth = model_.depth,
                          .width = model_.width,
                          .skipLayer = 0,  // the hash grid's features need no re-injection through a shallow trunk
                          .posDims = hash_.outputDims(),
                          // (an appearance vector enters as a bias on the colour layer, recordAppearance)
                          .dirDims = sh_.outputDims(),
                          .density = model_.density,
                          .seed = config.seed,
                          .featureWidth = model_.featureWidth},
           mlpTuningFor(ctx, training)),
      table_(ctx, "encoding", hash_.initialParameters(config.seed),
             training ? std::optional(fieldTableAdamOf(config, hashGridConfigFor(model_))) : std::nullopt, usedPartsOf(hash_)),
      network_(ctx, "mlp", mlp_.initialParameters(), training ? std::optional(adamConfigOf(config)) : std::nullopt),
      grid_(ctx, model_.gridResolution, model_.cascades),
      // The per-photo gradients (camera refinement, appearance) are summed over each photo's run of rays.
      rays_(ctx, rayCapacity_, model_.nearDistance > 0 ? model_.nearDistance : kNearPlane,
            model_.refineCameras || model_.appearanceDims > 0),
      marcher_(ctx, rayCapacity_),
      points_(ctx),
      compositor_(ctx),
      color_(gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity_) * 16)),
      depth_(gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity_) * 4)),
      marched_(ctx, rayCapacity_, sampleCapacity_),
      field_(ctx, mlp_, sampleCapacity_, training),
      weights_(gpu::Buffer::zeros(ctx, VkDeviceSize(sampleCapacity_) * 4, "the compositing weights")),
      wholeRays_(gpu::Buffer::zeros(ctx, 16)),
      segments_(ctx, rayCapacity_),
      renderMinTransmittance_(overrides.minTransmittance),
      raysFor_{std::min(rayCapacity_, 1024u), std::min(rayCapacity_, 1024u)},
      segmentsBelowKept_(kSegmentsBelowKept) {
  if (!(dt_ > 0) || !std::isfinite(dt_)) throw Error("fast model: the scene box is empty");
  // Checked against the photos when they are known (a model without the embedding: makeFieldPipeline).
  renderPhoto_ = overrides.appearancePhoto;
  if (!(renderMinTransmittance_ >= 0 && renderMinTransmittance_ < 1))
    throw Error("render settings: minTransmittance must be in [0, 1), got " + std::to_string(renderMinTransmittance_));
  if (model_.farField == FarField::Learned)
    farField_.emplace(ctx, rayCapacity_, config.seed, config.background, training ? std::optional(tableAdamOf(config)) : std::nullopt,
                      training ? std::optional(adamConfigOf(config)) : std::nullopt);
  if (training) allocateTraining(ctx);
  gpu::Recorder rec(ctx);
  rec.begin();
  grid_.recordMarkAllOccupied(rec);  // nothing is skipped until the field has been measured
  rec.end();
  rec.submitAndWait();
}

// The loss, gradients, occupancy update and early termination buffers of a training pipeline.
void FastPipeline::allocateTraining(Context& ctx) {
  loss_.emplace(ctx);
  dColor_ = gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity_) * 16);
  zeroDepthGrad_ = gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity_) * 4);
  partials_ = gpu::Buffer::zeros(ctx, gpu::groupsFor(rayCapacity_, nerf::PhotometricLoss::kRaysPerPartial) * 4);
  dPos_ = gpu::Buffer::zeros(ctx, VkDeviceSize(sampleCapacity_) * mlp_.posStride() * 4, "the encoding gradients");
  occPoints_ = std::min(grid_.numCells(), kMaxOccupancyPoints);
  occPositions_ = gpu::Buffer::zeros(ctx, VkDeviceSize(occPoints_) * nerf::kPointBytes, "the occupancy update's points");
  occFeatures_ = gpu::Buffer::zeros(ctx, VkDeviceSize(occPoints_) * mlp_.posStride() * 4,
                                    "the occupancy update's position encodings");
  occDensity_ = gpu::Buffer::zeros(ctx, VkDeviceSize(occPoints_) * 4, "the occupancy update's densities");
  occCells_ = gpu::Buffer::zeros(ctx, VkDeviceSize(occPoints_) * 4);
  for (auto& counts : stepCounts_) counts = gpu::Buffer::hostReadable(ctx, 16, "a training step's counts");
  if (model_.earlyTermination) {
    kept_.emplace(ctx, rayCapacity_, sampleCapacity_);
    gatherBackward_ = sampleCapacity_ <= mlp_.chunkRows();
    if (gatherBackward_) segmentRows_.emplace(ctx, sampleCapacity_);
  }
}

void FastPipeline::recordMarch(gpu::Recorder& rec, const nerf::RaySpan& rays, uint32_t maxSamples, uint32_t seed,
                               bool jitter) {
  marcher_.record(rec, rays, grid_, box_, {dt_, maxSamples, seed, jitter, cone_}, marched_.view());
}

void FastPipeline::recordField(gpu::Recorder& rec, const nerf::RaySpan& rays, bool keep) {
  FieldBatch& f = field_;
  const uint32_t count = sampleCapacity_;
  const nerf::PackedSamples batch = marched_.view();
  points_.record(rec, count, rays.range, batch, box_, {f.positions, f.directions});
  const std::optional<nerf::RowBias> colourBias = recordAppearance(rec, keep);
  // A training step runs in segments, the field over the rows the compositor will read, once the
  // last step kept few of its marched samples; while rays keep most of theirs (early in training),
  // segments would only add dispatches.
  if (!keep || !segmentRows_ || lastKeptFraction_ > segmentsBelowKept_)
    return recordFieldRows(rec, batch.total(), std::nullopt, colourBias, keep);
  const float maxDepth = nerf::Compositor::maxOpticalDepth(kMinTransmittance);
  for (size_t s = 0; s + 1 < kTrainingSegments.size(); ++s) {
    segmentRows_->record(rec, rays.count, batch, gpu::BufferRange(f.field), maxDepth, kTrainingSegments[s],
                         kTrainingSegments[s + 1]);
    recordFieldRows(rec, segmentRows_->count(), gpu::BufferRange(segmentRows_->rows()), colourBias, true);
  }
}

void FastPipeline::recordFieldRows(gpu::Recorder& rec, const gpu::BufferRange& limit,
                                   const std::optional<gpu::BufferRange>& gather,
                                   const std::optional<nerf::RowBias>& colourBias, bool keep) {
  FieldBatch& f = field_;
  const uint32_t count = sampleCapacity_;
  hash_.recordForward(rec, {count, f.positions, f.posFeatures, mlp_.posStride(), 0, limit, gather}, table_.params());
  sh_.recordForward(rec, {count, f.directions, f.dirFeatures, mlp_.dirStride(), 0, limit, gather});
  nerf::NerfRows rows = f.mlpRows(count);
  rows.rowLimit = limit;
  rows.colourBias = colourBias;
  rows.rowGather = gather;
  mlp_.recordForward(rec, rows, network_.params(), keep ? f.workspace.get() : nullptr);
}

nerf::CompositeInputs FastPipeline::compositeInputs(uint32_t first, uint32_t count, const std::array<float, 3>& background) {
  nerf::CompositeInputs in = nerf::CompositeInputs::packed(count, marched_.view(), field_.field);
  in.background = background;
  in.perRayBackground = rays_.backgrounds(first, count);
  return in;
}

void FastPipeline::doRecordRender(gpu::Recorder& rec, const ViewBlock& view, bool mayWait) {
  const uint32_t count = view.count;
  if (count > rayCapacity_)
    throw Error("fast model: render block of " + std::to_string(count) + " rays over capacity " + std::to_string(rayCapacity_));
  if (count == 0) return;
  rays_.recordView(rec, view, box_);
  if (farField_) farField_->recordForward(rec, count, rays_.rays(), rays_.background(), false);
  // A tile marched in segments, each ray stopped where it has turned opaque (SegmentAccumulator).
  // The first segment gives every ray kFirstSegment samples. Recorded into a caller's command buffer
  // (no host read-back), every ray of the tile gets the same number of segments, up to
  // capacity / count samples in all (the ended rays march none; the field's kernels are recorded
  // for the capacity and skip the rows past the device's sample total, shaders/gpu/row_limit.glsl).
  // Otherwise, after each segment's submission, the host reads how many rays are still live (not
  // yet opaque, their march not done), and the next segment gives those as many samples as the
  // capacity holds for them, up to the model's samples per ray in all; a block then holds as many
  // rays as the sample capacity gives kFirstSegment samples each (the whole tile when the pipeline
  // was built for rendering).
  const uint32_t most = mayWait ? model_.maxSamplesPerRay
                                : std::max(1u, std::min(model_.maxSamplesPerRay, sampleCapacity_ / count));
  const uint32_t block =
      mayWait ? std::min(count, std::max(kRayAlign, sampleCapacity_ / kFirstSegment / kRayAlign * kRayAlign)) : count;
  for (uint32_t done = 0; done < count; done += block) {
    const uint32_t n = std::min(block, count - done);
    const nerf::RaySpan rays = rays_.rays(done, n);
    const nerf::SegmentAccumulator::Gathered gathered{rays_.backgrounds(done, n), gpu::rowsOf(color_, nerf::kColorBytes, done, n),
                                                gpu::rowsOf(depth_, nerf::kDepthBytes, done, n)};
    for (uint32_t marched = 0, live = n; live > 0 && marched < most;) {
      const uint32_t cap = std::min({std::max(1u, sampleCapacity_ / live), marched == 0 || !mayWait ? kFirstSegment : most,
                                     most - marched});
      const bool first = marched == 0, last = marched + cap >= most;
      if (mayWait) segments_.recordResetCounts(rec);
      recordMarch(rec, rays, cap, 0, false);
      recordField(rec, rays, false);
      compositor_.recordForward(rec, nerf::CompositeInputs::packed(n, marched_.view(), field_.field),
                                {segments_.segmentColor(), segments_.segmentDepth(), weights_});
      segments_.record(rec, {cap, first, last, renderMinTransmittance_}, rays, marched_.view(), gathered);
      marched += cap;
      if (!mayWait) continue;
      rec.end();
      rec.submitAndWait();
      rec.begin();
      renderedSamples_ += segments_.samples();
      live = segments_.active();
    }
  }
}

void FastPipeline::recordFieldAt(gpu::Recorder& rec, FieldBatch& f, uint32_t count) {
  hash_.recordForward(rec, {count, f.positions, f.posFeatures, mlp_.posStride(), 0}, table_.params());
  sh_.recordForward(rec, {count, f.directions, f.dirFeatures, mlp_.dirStride(), 0});
  nerf::NerfRows rows = f.mlpRows(count);
  rows.colourBias = recordAppearance(rec, false);
  mlp_.recordForward(rec, rows, network_.params(), nullptr);
}

std::optional<nerf::RowBias> FastPipeline::recordAppearance(gpu::Recorder& rec, bool training) {
  if (!model_.appearanceDims) return std::nullopt;
  if (!appearance_)
    throw Error("fast model: model.appearance_dims is " + std::to_string(model_.appearanceDims) +
                ", but the number of training photos (whose vectors it learns) was never given");
  if (!training) return appearance_->recordRenderBias(rec);
  return appearance_->recordTrainingBias(rec, marched_.sampleRay, rays_.pixelIds());
}

void FastPipeline::recordOccupancyUpdate(gpu::Recorder& rec, uint32_t step) {
  const uint32_t seed = core::pcgHash(config_.seed * 31u + step + 0x5bd1e995u);
  uint32_t count;
  if (step < model_.gridWarmupSteps && grid_.numCells() <= occPoints_) {
    count = grid_.numCells();
    grid_.recordAllCellPoints(rec, seed, occPositions_, occCells_);
  } else {
    // After warm-up a quarter of the cells per update (with repetition) keeps up with the field.
    count = step < model_.gridWarmupSteps ? occPoints_ : std::max(1u, occPoints_ / 4);
    grid_.recordRandomCellPoints(rec, seed, count, occPositions_, occCells_);
  }
  // instant-ngp's threshold: the density at which one step is 1% opaque, or the grid's mean density
  // (before this update, computed on the device; a cell no camera sees counts as 0) when that is
  // lower, so that a young field whose densities are all small is not declared empty everywhere
  // (nothing would be sampled, and nothing learnt).
  const float threshold = nerf::OccupancyGrid::densityThreshold(kOccupancyThickness, trainedDt_);
  // The density alone: the colour branch would cost more than the trunk and is not looked at.
  hash_.recordForward(rec, {count, occPositions_, occFeatures_, mlp_.posStride(), 0}, table_.params());
  mlp_.recordDensity(rec, count, network_.params(), occFeatures_, occDensity_);
  const float decay = nerf::OccupancyGrid::decayFor(kOccupancyDecay, count, grid_.numCells());
  grid_.recordUpdate(rec, {occCells_, occDensity_, count}, {decay, threshold, true});
}

uint32_t FastPipeline::doRecordTrainStep(gpu::Recorder& rec, const TrainingData& data, nerf::OptimizerStep at) {
  if (!training_) throw Error("fast model: pipeline was not built for training");
  const uint32_t step = at.step;
  const uint32_t seed = stepSeed(config_, step);
  if (model_.gridUpdateInterval && step % model_.gridUpdateInterval == 0 && step > 0) recordOccupancyUpdate(rec, step);
  // With camera refinement the step's rays come from the cameras as corrected so far.
  TrainingData cameras = data;
  if (cameras_) {
    if (data.numCameras != cameras_->numCameras())
      throw Error("fast model: " + std::to_string(data.numCameras) + " training cameras, but camera refinement was set up for " +
                  std::to_string(cameras_->numCameras()));
    cameras_->recordApply(rec, *data.cameras);
    cameras.cameras = &cameras_->cameras();
  }
  // The per-photo sums find a photo's rays by the runs the batch was drawn in over data.numCameras.
  if (appearance_ && data.numCameras != appearance_->numPhotos())
    throw Error("fast model: " + std::to_string(data.numCameras) + " training photos, but the appearance embedding was set up for " +
                std::to_string(appearance_->numPhotos()));
  const uint32_t slot = slotOf(step);
  const nerf::RaySpan batch = recordTrainingBatch(rec, cameras, seed, raysFor_[slot]);
  const nerf::CompositeInputs composite = recordTrainingForward(rec, cameras, batch);
  recordTrainingBackward(rec, batch, composite);
  network_.recordOptimizerStep(rec, at);
  table_.recordOptimizerStep(rec, at);
  if (farField_) farField_->recordOptimizerStep(rec, at);
  if (cameras_) cameras_->recordOptimizerStep(rec, at);
  if (appearance_) appearance_->recordOptimizerStep(rec, at);
  recordStepCounts(rec, batch.count, stepCounts_[slot]);
  return batch.count;
}

nerf::RaySpan FastPipeline::recordTrainingBatch(gpu::Recorder& rec, const TrainingData& data, uint32_t seed, uint32_t R) {
  rays_.recordTraining(rec, data, seed, R, box_, config_);
  if (farField_) farField_->recordForward(rec, R, rays_.rays(), rays_.background(), true);
  const nerf::RaySpan batch = rays_.rays(0, R);
  recordMarch(rec, batch, model_.maxSamplesPerRay, seed, true);
  // The batch's size stays on the device: the rays that fit the sample capacity whole, and their
  // sample total (the march's totals, rewritten); every later kernel is recorded for the capacity
  // and cut to those counts (shaders/gpu/row_limit.glsl), so the step is one submission.
  marcher_.recordCutToWholeRays(rec, {R, sampleCapacity_, kRayAlign}, marched_.view(), wholeRayCount());
  return batch;
}

nerf::CompositeInputs FastPipeline::recordTrainingForward(gpu::Recorder& rec, const TrainingData& data,
                                                    const nerf::RaySpan& batch) {
  // The field forward with activations kept, in segments over the samples in front of each ray's
  // cut (SegmentRows). The compositor stops each ray where the transmittance falls below 1e-4
  // (instant-ngp's early termination) and gives the samples behind that zero gradient, so the step
  // needs no separate pass (the field without gradients, then a compacted copy of the kept samples)
  // and never evaluates a sample twice; the backward then runs over the kept samples alone, reading
  // the forward's rows through their packed index (KeptRows).
  // The rays past the whole ones have no samples: the loss neither counts them nor gives them a gradient.
  const uint32_t R = batch.count;
  nerf::CompositeInputs composite = compositeInputs(0, R, config_.background);
  if (model_.earlyTermination) composite.maxOpticalDepth = nerf::Compositor::maxOpticalDepth(kMinTransmittance);
  nerf::CompositeOutputs composited{gpu::rowsOf(color_, nerf::kColorBytes, 0, R), gpu::rowsOf(depth_, nerf::kDepthBytes, 0, R), weights_};
  if (kept_) composited.keptCounts = gpu::rowsOf(kept_->counts(), sizeof(uint32_t), 0, R);
  recordField(rec, batch, true);
  compositor_.recordForward(rec, composite, composited);
  loss_->record(rec, {R, color_, rays_.pixelIds(), rays_.background(), wholeRayCount()},
                {data.pixels, *data.cameras}, {dColor_, partials_});
  return composite;
}

void FastPipeline::recordTrainingBackward(gpu::Recorder& rec, const nerf::RaySpan& batch, const nerf::CompositeInputs& composite) {
  const uint32_t R = batch.count;
  // The distortion loss, a mean over the batch's rays like the photometric loss (over the R rays
  // recorded: the rays past the device's cut have no samples, so they add nothing), its distances
  // even in the march's steps.
  const nerf::DistortionLoss distortion{model_.distortionLoss / float(R), cone_.coneAngle, dt_, std::max(dt_, cone_.dtMax),
                                  batch.range};
  compositor_.recordBackward(rec, composite, {dColor_, zeroDepthGrad_, field_.dField, distortion});
  if (farField_) farField_->recordBackward(rec, R, *composite.perRayBackground, color_, dColor_);
  // With the kept samples packed, the backward runs over them alone: the MLP's reads the forward's
  // rows through their index, the hash grid's reads the kept positions beside the packed encoding
  // gradients. Else it runs over every marched sample.
  gpu::BufferRange positions(field_.positions), limit = marched_.view().total();
  nerf::NerfGradients gradients{field_.dField, network_.grads(), gpu::BufferRange(dPos_)};
  if (gatherBackward_) {
    kept_->record(rec, R, marched_.offsets, field_.positions);
    positions = kept_->positions(), limit = kept_->total(), gradients.rowGather = kept_->rows();
  }
  // The appearance embedding trains from the colour layer's pre-activation gradient.
  if (appearance_) gradients.dColour = gpu::BufferRange(dColour_);
  nerf::NerfRows rows = field_.mlpRows(sampleCapacity_);
  rows.rowLimit = limit;
  mlp_.recordBackward(rec, rows, network_.params(), gradients, *field_.workspace);
  const gpu::Buffer& rowOffsets = gatherBackward_ ? kept_->offsets() : marched_.offsets;
  if (appearance_)
    appearance_->recordGradient(rec, {R, rays_.pixelIds(), rowOffsets, dColour_, wholeRayCount()});
  const nerf::EncodedRows encoded{sampleCapacity_, positions, dPos_, mlp_.posStride(), 0, limit};
  // Camera refinement: the table's backward also gives dL/dp (from the table before its optimizer
  // step), which the per-camera sums then carry to the poses.
  std::optional<nerf::PositionGradientTarget> position;
  if (cameras_) position = nerf::PositionGradientTarget{table_.params(), dPosition_};
  hash_.recordBackward(rec, encoded, table_.grads(), position);
  if (cameras_) recordCameraGradient(rec, batch, rowOffsets);
}

void FastPipeline::recordCameraGradient(gpu::Recorder& rec, const nerf::RaySpan& batch, const gpu::BufferRange& rowOffsets) {
  // The learned far field's colour also depends on the direction; that part is left out (its
  // gradient is small and blurred: a colour per direction at infinity).
  cameras_->recordGradient(rec, {batch, rays_.pixelIds(), marched_.offsets, rowOffsets, marched_.samples, dPosition_,
                                 wholeRayCount(), box_});
}

void FastPipeline::setTrainingCameras(uint32_t count) {
  gpu::MemoryAccount::Scope charge(memory());
  if (model_.appearanceDims) {
    // W_a starts as the colour layer's weights would with the vector among its inputs.
    const core::DenseShape& colour = mlp_.shape().colour();
    const AppearanceInit init{config_.seed, float(1.0 / std::sqrt(double(colour.ka + colour.kb + model_.appearanceDims)))};
    appearance_.emplace(ctx_, count, model_.appearanceDims, colour.n4(), init,
                        training_ ? std::optional(adamConfigOf(config_)) : std::nullopt, renderPhoto_);
    if (training_)
      dColour_ = gpu::Buffer::zeros(ctx_, VkDeviceSize(sampleCapacity_) * colour.n4() * 4,
                                    "the samples' colour-layer gradients");
  }
  if (!training_ || !model_.refineCameras) return;
  CameraRefinementSettings settings;
  settings.adam = adamConfigOf(config_, model_.cameraLearningRate / config_.learningRate);
  settings.penalty = model_.cameraPenalty;
  cameras_.emplace(ctx_, count, settings);
  dPosition_ = gpu::Buffer::zeros(ctx_, VkDeviceSize(sampleCapacity_) * 16, "the samples' position gradients");
}

std::vector<std::array<float, 6>> FastPipeline::cameraCorrections() {
  return cameras_ ? cameras_->corrections() : std::vector<std::array<float, 6>>{};
}

void FastPipeline::recordStepCounts(gpu::Recorder& rec, uint32_t R, gpu::Buffer& counts) {
  // What the host reads of a step, copied within the step's own recording into host-readable
  // memory, one buffer per step in flight: after the step's fence the host reads three words with
  // no transfer of its own (a download of a discrete GPU's buffer is a submission and a wait
  // each), and the per-ray kept counts are summed on the device, not read back (up to 1 MB a step).
  rec.copy(wholeRays_, counts, 4, 0, 0);
  rec.copy(marched_.totals, counts, 4, 0, 4);
  if (!model_.earlyTermination) return;
  if (!gatherBackward_) kept_->recordTotal(rec, R);  // else the backward's packing made it
  rec.copy(kept_->totals(), counts, 4, 0, 8);
}

FieldPipeline::StepSize FastPipeline::doCollectTrainStep(uint32_t slot) {
  // The step's counts (recordStepCounts), read after its own wait.
  const auto counts = stepCounts_[slot].download<uint32_t>(3);
  const uint32_t rays = counts[0], marchedCount = counts[1];
  marchedSamples_ += marchedCount;
  marchedRays_ += rays;
  // The samples the loss saw (all marched ones without early termination).
  const uint32_t samples = model_.earlyTermination ? counts[2] : marchedCount;
  keptSamples_ += samples;

  lastRays_ = rays;
  lastSamples_ = marchedCount;
  // The step kStepsInFlight later (the next one to use this slot): as many rays as this step's
  // marched samples per ray say fit the sample budget.
  const double samplesPerRay = rays ? std::max(1.0, double(marchedCount) / rays) : 1.0;
  lastSamplesPerRay_ = rays ? double(marchedCount) / rays : 0.0;
  lastKeptFraction_ = marchedCount ? double(samples) / marchedCount : 1.0;
  raysFor_[slot] = uint32_t(std::clamp(double(model_.samplesPerBatch) / samplesPerRay, double(kRayAlign), double(rayCapacity_)));
  return {rays, samples};
}

std::vector<StateArray> FastPipeline::state() {
  std::vector<StateArray> s;
  table_.appendState(s);
  network_.appendState(s);
  if (cameras_) cameras_->appendState(s);
  if (appearance_) appearance_->appendState(s);
  if (farField_) farField_->appendState(s);
  s.push_back({"occupancy.density", &grid_.density(), grid_.numCells(), false});
  // uint words, carried bit for bit through the float section
  s.push_back({"occupancy.bits", &grid_.bits(), grid_.numWords(), false, false});
  return s;
}

ModelStatistics FastPipeline::modelStatistics() {
  // The box the occupied cells span: what the scene needs of the box it was given (one cascade).
  auto bits = grid_.bits().download<uint32_t>(grid_.numWords());
  const uint32_t res = grid_.resolution();
  uint32_t lo[3] = {res, res, res}, hi[3] = {0, 0, 0};
  for (uint32_t i = 0; i < grid_.numCells() && grid_.cascades() == 1; ++i) {
    if (!((bits[i >> 5] >> (i & 31)) & 1u)) continue;
    const uint32_t c[3] = {i % res, (i / res) % res, i / (res * res)};
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k] + 1);
  }
  double boxFraction = 1;
  for (int k = 0; k < 3; ++k) boxFraction *= hi[k] > lo[k] ? double(hi[k] - lo[k]) / res : 0.0;
  ModelStatistics s;
  s.mlpParameters = network_.count();
  s.encodingParameters = table_.count();
  s.samplesPerRay = lastSamplesPerRay_;
  s.raysPerStep = lastRays_;
  s.samplesPerStep = lastSamples_;
  s.occupiedFraction = grid_.occupiedFraction();
  s.occupiedFractionPerCascade = grid_.occupiedFractionPerCascade();
  if (grid_.cascades() == 1) s.occupiedBoxFraction = boxFraction;
  if (marchedRays_) s.meanSamplesPerRay = double(marchedSamples_) / double(marchedRays_);
  s.keptByEarlyTermination = marchedSamples_ ? double(keptSamples_) / double(marchedSamples_) : 1.0;
  return s;
}

}  // namespace vknerf::models

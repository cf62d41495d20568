#include "models/fast/fast_pipeline.h"

#include <algorithm>
#include <cmath>

#include "nerf/sampling/points.h"
#include "reference/rng.h"
#include "vknerf/error.h"

namespace vknerf::nerf {

namespace {

constexpr float kOccupancyDecay = 0.95f;       // instant-ngp's EMA factor per update
constexpr float kOccupancyThickness = 0.01f;   // a cell is empty when one step through it is < 1% opaque
constexpr uint32_t kMaxOccupancyPoints = 1u << 18;
constexpr uint32_t kRayAlign = 64;             // sub-batches start at multiples of this (binding offsets)

float diagonal(const Aabb& b) {
  float s = 0;
  for (int k = 0; k < 3; ++k) s += (b.max[k] - b.min[k]) * (b.max[k] - b.min[k]);
  return std::sqrt(s);
}

MlpConfig fastMlpConfig(const ModelConfig& m, uint32_t posDims, uint32_t dirDims, uint32_t seed) {
  MlpConfig c;
  c.depth = m.depth;
  c.width = m.width;
  c.skipLayer = 0;  // the hash grid's features need no re-injection through a shallow trunk
  c.posDims = posDims;
  c.dirDims = dirDims;
  c.density = static_cast<DensityActivation>(m.density);
  c.seed = seed;
  return c;
}

}  // namespace

HashGridConfig hashGridConfigFor(const ModelConfig& m) {
  HashGridConfig c;
  c.levels = m.hashLevels;
  c.featuresPerLevel = m.hashFeatures;
  c.log2TableSize = m.hashLog2Size;
  c.baseResolution = m.hashBaseResolution;
  c.growthFactor = m.hashGrowth;
  return c;
}

FastPipeline::FastPipeline(Context& ctx, const TrainConfig& config, const Aabb& box, uint32_t rayCapacity,
                           bool training)
    : ctx_(ctx),
      config_(config),
      box_(box),
      rayCapacity_(std::max(rayCapacity, kRayAlign)),
      training_(training),
      dt_(diagonal(box) / float(std::max(config.model.renderMarchSteps ? config.model.renderMarchSteps
                                                                         : config.model.marchSteps, 1u))),
      trainedDt_(diagonal(box) / float(std::max(config.model.marchSteps, 1u))),
      hash_(ctx, hashGridConfigFor(config.model)),
      sh_(ctx, config.model.shDegree),
      mlp_(ctx, fastMlpConfig(config.model, hash_.outputDims(), sh_.outputDims(), config.seed)),
      grid_(ctx, config.model.gridResolution),
      rayGen_(ctx),
      marcher_(ctx, std::max(rayCapacity, kRayAlign)),
      points_(ctx),
      compositor_(ctx),
      backgrounds_(ctx),
      raysNext_(std::min(std::max(rayCapacity, kRayAlign), 1024u)) {
  const ModelConfig& m = config.model;
  if (m.marchSteps == 0 || m.maxSamplesPerRay == 0) throw Error("fast model: march steps and samples per ray must be > 0");
  if (!(dt_ > 0) || !std::isfinite(dt_)) throw Error("fast model: the scene box is empty");
  // A capacity that always holds kRayAlign whole rays, so every sub-batch makes progress.
  const uint64_t minimum = uint64_t(kRayAlign) * m.maxSamplesPerRay + kRayAlign;
  const uint64_t wanted = training ? 2ull * config.samplesPerBatch : uint64_t(rayCapacity_) * 64;
  allocate(uint32_t(std::min<uint64_t>(std::max(minimum, wanted), 1ull << 28)));

  hashParams_ = gpu::Buffer::of(ctx, hash_.initialParameters(config.seed));
  mlpParams_ = gpu::Buffer::of(ctx, mlp_.initialParameters());
  if (training) {
    loss_.emplace(ctx);
    AdamConfig ac = adamConfigOf(config);
    adamMlp_.emplace(ctx, ac);
    ac.skipZeroGradients = true;  // table entries no sample touched keep their moments (instant-ngp)
    adamHash_.emplace(ctx, ac);
    auto zeros = [&](size_t n) {
      gpu::Buffer b(ctx, n * sizeof(float));
      b.zero();
      return b;
    };
    hashGrads_ = zeros(hash_.parameterCount());
    hashM_ = zeros(hash_.parameterCount());
    hashV_ = zeros(hash_.parameterCount());
    mlpGrads_ = zeros(mlp_.parameterCount());
    mlpM_ = zeros(mlp_.parameterCount());
    mlpV_ = zeros(mlp_.parameterCount());
    workspace_ = std::make_unique<NerfMlp::Workspace>(ctx, mlp_, sampleCapacity_);
    if (config.earlyTermination) {
      termination_.emplace(ctx, rayCapacity_);
      auto zeros = [&](VkDeviceSize bytes) {
        gpu::Buffer b(ctx, bytes);
        b.zero();
        return b;
      };
      termOffsets_ = zeros((VkDeviceSize(rayCapacity_) + 1) * 4);
      termSamples_ = zeros(VkDeviceSize(sampleCapacity_) * kSampleBytes);
      termSampleRay_ = zeros(VkDeviceSize(sampleCapacity_) * 4);
      termTotals_ = zeros(RayMarcher::kTotalsBytes);
    }
  }
  gpu::Recorder rec(ctx);
  rec.begin();
  grid_.recordMarkAllOccupied(rec);  // nothing is skipped until the field has been measured
  rec.end();
  rec.submitAndWait();
}

void FastPipeline::allocate(uint32_t S) {
  sampleCapacity_ = S;
  const VkDeviceSize R = rayCapacity_;
  auto buf = [&](VkDeviceSize bytes) {
    gpu::Buffer b(ctx_, std::max<VkDeviceSize>(bytes, 16));
    b.zero();  // recorded renders evaluate the field over the whole capacity: no garbage inputs
    return b;
  };
  rays_ = buf(R * kRayBytes);
  pixelIds_ = buf(R * kPixelIdBytes);
  background_ = buf(R * 16);
  color_ = buf(R * 16);
  depth_ = buf(R * 4);
  offsets_ = buf((R + 1) * 4);
  totals_ = buf(RayMarcher::kTotalsBytes);
  samples_ = buf(VkDeviceSize(S) * kSampleBytes);
  sampleRay_ = buf(VkDeviceSize(S) * 4);
  positions_ = buf(VkDeviceSize(S) * kPointBytes);
  directions_ = buf(VkDeviceSize(S) * kPointBytes);
  posFeatures_ = buf(VkDeviceSize(S) * mlp_.posStride() * 4);
  dirFeatures_ = buf(VkDeviceSize(S) * mlp_.dirStride() * 4);
  field_ = buf(VkDeviceSize(S) * kFieldBytes);
  weights_ = buf(VkDeviceSize(S) * 4);
  if (training_) {
    dColor_ = buf(R * 16);
    zeroDepthGrad_ = buf(R * 4);
    partials_ = buf(gpu::groupsFor(rayCapacity_, PhotometricLoss::kRaysPerPartial) * 4);
    dField_ = buf(VkDeviceSize(S) * kFieldBytes);
    dPos_ = buf(VkDeviceSize(S) * mlp_.posStride() * 4);
    occPoints_ = std::min(grid_.numCells(), kMaxOccupancyPoints);
    occPositions_ = buf(VkDeviceSize(occPoints_) * kPointBytes);
    occCells_ = buf(VkDeviceSize(occPoints_) * 4);
    std::vector<float> up(size_t(occPoints_) * 4, 0.0f);
    for (size_t i = 0; i < occPoints_; ++i) up[i * 4 + 2] = 1.0f;  // any unit direction: sigma ignores it
    occDirections_ = gpu::Buffer::of(ctx_, up);
    occPosFeatures_ = buf(VkDeviceSize(occPoints_) * mlp_.posStride() * 4);
    occDirFeatures_ = buf(VkDeviceSize(occPoints_) * mlp_.dirStride() * 4);
    occField_ = buf(VkDeviceSize(occPoints_) * kFieldBytes);
  } else {
    occCells_ = buf(16);
  }
}

void FastPipeline::recordMarch(gpu::Recorder& rec, uint32_t rayOffset, uint32_t numRays, uint32_t maxSamples,
                               uint32_t seed, bool jitter) {
  marcher_.record(rec, gpu::BufferRange(rays_, VkDeviceSize(rayOffset) * kRayBytes, VkDeviceSize(numRays) * kRayBytes),
                  numRays, grid_, box_, dt_, maxSamples, seed, jitter, offsets_, samples_, sampleRay_, totals_);
}

std::pair<uint32_t, uint32_t> FastPipeline::wholeRays(uint32_t numRays) {
  const uint32_t total = totals_.download<uint32_t>(1)[0];
  if (total < sampleCapacity_) return {numRays, total};
  // The batch hit the capacity: the marcher clamped the offsets there, so a ray ending below it is whole.
  auto off = offsets_.download<uint32_t>(size_t(numRays) + 1);
  uint32_t whole = uint32_t(std::upper_bound(off.begin() + 1, off.end(), sampleCapacity_ - 1) - (off.begin() + 1));
  whole = std::max(kRayAlign, whole / kRayAlign * kRayAlign);
  whole = std::min(whole, numRays);
  return {whole, off[whole]};
}

void FastPipeline::recordField(gpu::Recorder& rec, const Packed& batch, uint32_t rayOffset, uint32_t count,
                               NerfMlp::Workspace* keep, bool limitToTotal) {
  points_.record(rec, gpu::BufferRange(rays_, VkDeviceSize(rayOffset) * kRayBytes, VK_WHOLE_SIZE), *batch.samples,
                 *batch.sampleRay, *batch.totals, sampleCapacity_, box_, positions_, directions_);
  // The sample total is the first uint of the totals (RayMarcher::kTotalsBytes).
  const gpu::BufferRange total(*batch.totals, 0, 4);
  const gpu::BufferRange* limit = limitToTotal ? &total : nullptr;
  hash_.recordForward(rec, positions_, count, hashParams_, posFeatures_, mlp_.posStride(), 0, limit);
  sh_.record(rec, directions_, count, dirFeatures_, mlp_.dirStride(), 0, limit);
  mlp_.recordForward(rec, count, mlpParams_, posFeatures_, dirFeatures_, field_, keep, limit);
}

void FastPipeline::recordComposite(gpu::Recorder& rec, const Packed& batch, uint32_t rayOffset, uint32_t numRays,
                                   const std::array<float, 3>& bg) {
  gpu::BufferRange perRay(background_, VkDeviceSize(rayOffset) * 16, VkDeviceSize(numRays) * 16);
  compositor_.recordForward(rec, numRays, 0, *batch.offsets, *batch.samples, field_, bg, &perRay,
                            gpu::BufferRange(color_, VkDeviceSize(rayOffset) * 16, VkDeviceSize(numRays) * 16),
                            gpu::BufferRange(depth_, VkDeviceSize(rayOffset) * 4, VkDeviceSize(numRays) * 4), weights_);
}

void FastPipeline::recordRender(gpu::Recorder& rec, const gpu::BufferRange& cameras, uint32_t camera, uint32_t first,
                                uint32_t count, const std::array<float, 3>& background, bool mayWait) {
  if (count > rayCapacity_)
    throw Error("fast model: render block of " + std::to_string(count) + " rays over capacity " + std::to_string(rayCapacity_));
  if (count == 0) return;
  rayGen_.recordImage(rec, cameras, camera, first, count, box_, kNearPlane, rays_, pixelIds_);
  backgrounds_.recordConstant(rec, background_, count, background);
  if (!mayWait) {
    // Everything in the caller's command buffer: each ray gets at most capacity / count samples, so
    // nothing is cut. The sample total is known only on the device: the field's kernels are
    // recorded for the whole capacity and skip the rows past the total (shaders/row_limit.glsl).
    const uint32_t maxSamples = std::max(1u, std::min(config_.model.maxSamplesPerRay, sampleCapacity_ / count));
    recordMarch(rec, 0, count, maxSamples, 0, false);
    recordField(rec, marched(), 0, sampleCapacity_, nullptr, true);
    recordComposite(rec, marched(), 0, count, background);
    return;
  }
  for (uint32_t done = 0; done < count;) {
    const uint32_t n = count - done;
    recordMarch(rec, done, n, config_.model.maxSamplesPerRay, 0, false);
    rec.end();
    rec.submitAndWait();
    auto [whole, samples] = wholeRays(n);
    rec.begin();
    recordField(rec, marched(), done, samples, nullptr);
    recordComposite(rec, marched(), done, whole, background);
    done += whole;
    if (done < count) {
      rec.end();
      rec.submitAndWait();
      rec.begin();
    }
  }
}

void FastPipeline::recordOccupancyUpdate(gpu::Recorder& rec, uint32_t step) {
  const uint32_t seed = ref::pcgHash(config_.seed * 31u + step + 0x5bd1e995u);
  uint32_t count;
  if (step < config_.gridWarmupSteps && grid_.numCells() <= occPoints_) {
    count = grid_.numCells();
    grid_.recordAllCellPoints(rec, seed, occPositions_, occCells_);
  } else {
    // After warm-up a quarter of the cells per update (with repetition) keeps up with the field.
    count = step < config_.gridWarmupSteps ? occPoints_ : std::max(1u, occPoints_ / 4);
    grid_.recordRandomCellPoints(rec, seed, count, occPositions_, occCells_);
  }
  // instant-ngp's threshold: the density at which one step is 1% opaque, or the grid's mean density
  // when that is lower, so that a young field whose densities are all small is not declared empty
  // everywhere (nothing would be sampled, and nothing learnt). The mean is the last update's; the
  // grid is host-visible or small, and this runs every K steps.
  auto density = grid_.density().download<float>(grid_.numCells());
  double sum = 0;
  for (float d : density) sum += std::isfinite(d) ? d : 0.0f;
  const float threshold = std::min(OccupancyGrid::densityThreshold(kOccupancyThickness, trainedDt_),
                                   float(sum / double(density.size())));
  hash_.recordForward(rec, occPositions_, count, hashParams_, occPosFeatures_, mlp_.posStride(), 0);
  sh_.record(rec, occDirections_, count, occDirFeatures_, mlp_.dirStride(), 0);
  mlp_.recordForward(rec, count, mlpParams_, occPosFeatures_, occDirFeatures_, occField_, nullptr);
  grid_.recordUpdate(rec, occCells_, occField_, count, kOccupancyDecay, threshold, 4, 3);
}

FieldPipeline::StepSize FastPipeline::trainStep(gpu::Recorder& rec, const TrainingData& data, uint32_t step) {
  if (!training_) throw Error("fast model: pipeline was not built for training");
  const uint32_t seed = ref::pcgHash(config_.seed * 7919u + step);
  const float lr = config_.learningRate *
                   std::pow(config_.learningRateFinal / config_.learningRate, float(step) / float(config_.decaySteps));
  const uint32_t R = raysNext_;
  rec.begin();
  if (config_.gridUpdateInterval && step % config_.gridUpdateInterval == 0 && step > 0) recordOccupancyUpdate(rec, step);
  rayGen_.recordRandom(rec, *data.cameras, data.numCameras, seed, R, box_, kNearPlane, rays_, pixelIds_);
  if (config_.randomBackground)
    backgrounds_.recordRandom(rec, background_, R, seed);
  else
    backgrounds_.recordConstant(rec, background_, R, config_.background);
  recordMarch(rec, 0, R, config_.model.maxSamplesPerRay, seed, true);
  rec.end();
  rec.submitAndWait();
  auto [rays, samples] = wholeRays(R);
  const uint32_t marchedCount = samples;
  marchedSamples_ += samples;

  Packed batch = marched();
  if (termination_) {
    // instant-ngp's two passes: the field without gradients over everything marched, then the
    // training pass (forward with activations kept, backward) only over the samples in front of
    // T < 1e-4 — behind an opaque surface the gradient is ~0 and the backward costs most.
    rec.begin();
    recordField(rec, batch, 0, samples, nullptr);
    termination_->record(rec, rays, offsets_, samples_, sampleRay_, field_, 1e-4f, termOffsets_, termSamples_,
                         termSampleRay_, dField_, termTotals_);
    rec.end();
    rec.submitAndWait();
    batch = terminated();
    samples = termTotals_.download<uint32_t>(1)[0];
  }
  keptSamples_ += samples;

  rec.begin();
  recordField(rec, batch, 0, samples, workspace_.get());
  recordComposite(rec, batch, 0, rays, config_.background);
  loss_->record(rec, rays, color_, pixelIds_, *data.images, *data.cameras, background_, dColor_, partials_);
  gpu::BufferRange perRay(background_, 0, VkDeviceSize(rays) * 16);
  compositor_.recordBackward(rec, rays, 0, *batch.offsets, *batch.samples, field_, config_.background, &perRay,
                             dColor_, zeroDepthGrad_, dField_);
  gpu::BufferRange dPos(dPos_);
  mlp_.recordBackward(rec, samples, mlpParams_, posFeatures_, dirFeatures_, field_, dField_, mlpGrads_, *workspace_,
                      &dPos);
  hash_.recordBackward(rec, positions_, samples, dPos_, mlp_.posStride(), 0, hashGrads_);
  adamMlp_->record(rec, mlpParams_, mlpGrads_, mlpM_, mlpV_, uint32_t(mlp_.parameterCount()), step + 1, lr);
  adamHash_->record(rec, hashParams_, hashGrads_, hashM_, hashV_, uint32_t(hash_.parameterCount()), step + 1,
                    lr * config_.hashLearningRateScale);
  rec.end();
  rec.submitAndWait();

  lastRays_ = rays;
  lastSamples_ = marchedCount;
  // Next step: as many rays as this step's marched samples per ray say fit the sample budget.
  const double samplesPerRay = rays ? std::max(1.0, double(marchedCount) / rays) : 1.0;
  lastSamplesPerRay_ = rays ? double(marchedCount) / rays : 0.0;
  raysNext_ = uint32_t(std::clamp(double(config_.samplesPerBatch) / samplesPerRay, double(kRayAlign), double(rayCapacity_)));
  return {rays, samples};
}

std::vector<StateArray> FastPipeline::state() {
  std::vector<StateArray> s = {{"encoding.params", &hashParams_, hash_.parameterCount(), false},
                               {"mlp.params", &mlpParams_, mlp_.parameterCount(), false},
                               {"occupancy.density", &grid_.density(), grid_.numCells(), false},
                               // uint words, carried bit for bit through the float section
                               {"occupancy.bits", &grid_.bits(), grid_.numWords(), false}};
  if (training_) {
    s.push_back({"encoding.adam_m", &hashM_, hash_.parameterCount(), true});
    s.push_back({"encoding.adam_v", &hashV_, hash_.parameterCount(), true});
    s.push_back({"mlp.adam_m", &mlpM_, mlp_.parameterCount(), true});
    s.push_back({"mlp.adam_v", &mlpV_, mlp_.parameterCount(), true});
  }
  return s;
}

std::vector<std::pair<std::string, double>> FastPipeline::statistics() {
  VkDeviceSize bytes = 0;
  for (const gpu::Buffer* b : {&hashParams_, &hashGrads_, &hashM_, &hashV_, &mlpParams_, &mlpGrads_, &mlpM_, &mlpV_,
                               &rays_, &pixelIds_, &background_, &color_, &depth_, &dColor_, &zeroDepthGrad_,
                               &partials_, &offsets_, &samples_, &sampleRay_, &totals_, &positions_, &directions_,
                               &posFeatures_, &dirFeatures_, &field_, &weights_, &dField_, &dPos_, &occPositions_,
                               &occCells_, &occDirections_, &occPosFeatures_, &occDirFeatures_, &occField_,
                               &termOffsets_, &termSamples_, &termSampleRay_, &termTotals_,
                               &grid_.density(), &grid_.bits()})
    bytes += b->valid() ? b->size() : 0;
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
  return {{"occupied fraction", grid_.occupiedFraction()},
          {"occupied cells' bounding box / scene box (volume)", boxFraction},
          {"samples per ray (last step)", lastSamplesPerRay_},
          {"rays per step (last step)", double(lastRays_)},
          {"samples per step (last step)", double(lastSamples_)},
          {"samples kept by early termination (all steps)",
           marchedSamples_ ? double(keptSamples_) / double(marchedSamples_) : 1.0},
          {"parameters (hash grid)", double(hash_.parameterCount())},
          {"parameters (MLP)", double(mlp_.parameterCount())},
          {"device buffers MiB (excl. MLP workspace)", double(bytes) / (1 << 20)}};
}

}  // namespace vknerf::nerf

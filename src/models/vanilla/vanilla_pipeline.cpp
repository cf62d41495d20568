#include "models/vanilla/vanilla_pipeline.h"

#include <cmath>

#include "reference/rng.h"

#include "vknerf/error.h"

namespace vknerf::nerf {

MlpConfig mlpConfigFor(const ModelConfig& m, uint32_t seed) {
  MlpConfig c;
  c.depth = m.depth;
  c.width = m.width;
  c.skipLayer = m.skipLayer;
  c.posDims = 3 + 6 * m.posLevels;
  c.dirDims = 3 + 6 * m.dirLevels;
  c.density = static_cast<DensityActivation>(m.density);
  c.seed = seed;
  return c;
}

namespace {

NetworkState makeNetwork(Context& ctx, const ModelConfig& model, uint32_t seed, bool training) {
  NetworkState n;
  n.mlp = std::make_unique<NerfMlp>(ctx, mlpConfigFor(model, seed));
  n.params = gpu::Buffer::of(ctx, n.mlp->initialParameters());
  if (training) {
    const VkDeviceSize bytes = n.mlp->parameterCount() * sizeof(float);
    n.grads = gpu::Buffer(ctx, bytes);
    n.m = gpu::Buffer(ctx, bytes);
    n.v = gpu::Buffer(ctx, bytes);
    n.grads.zero();
    n.m.zero();
    n.v.zero();
  }
  return n;
}

void allocateLevel(Context& ctx, LevelBuffers& l, const NerfMlp& mlp, uint32_t rays, uint32_t spr, bool training) {
  const VkDeviceSize n = VkDeviceSize(rays) * spr;
  l.samplesPerRay = spr;
  l.samples = gpu::Buffer(ctx, n * kSampleBytes);
  l.positions = gpu::Buffer(ctx, n * kPointBytes);
  l.directions = gpu::Buffer(ctx, n * kPointBytes);
  l.posFeatures = gpu::Buffer(ctx, n * mlp.posStride() * sizeof(float));
  l.dirFeatures = gpu::Buffer(ctx, n * mlp.dirStride() * sizeof(float));
  l.field = gpu::Buffer(ctx, n * kFieldBytes);
  l.color = gpu::Buffer(ctx, VkDeviceSize(rays) * 16);
  l.depth = gpu::Buffer(ctx, VkDeviceSize(rays) * 4);
  l.weights = gpu::Buffer(ctx, n * 4);
  if (training) {
    l.dField = gpu::Buffer(ctx, n * kFieldBytes);
    l.dColor = gpu::Buffer(ctx, VkDeviceSize(rays) * 16);
    l.partials = gpu::Buffer(ctx, gpu::groupsFor(rays, PhotometricLoss::kRaysPerPartial) * sizeof(float));
    l.workspace = std::make_unique<NerfMlp::Workspace>(ctx, mlp, uint32_t(n));
  }
}

}  // namespace

VanillaPipeline::VanillaPipeline(Context& ctx, const TrainConfig& config, const Aabb& box, uint32_t rayCapacity,
                                 bool training)
    : ctx_(ctx),
      config_(config),
      box_(box),
      capacity_(rayCapacity),
      training_(training),
      rayGen_(ctx),
      stratified_(ctx),
      pdf_(ctx),
      points_(ctx),
      posEncoding_(ctx, 3, config.model.posLevels, true),
      dirEncoding_(ctx, 3, config.model.dirLevels, true),
      compositor_(ctx),
      backgrounds_(ctx) {
  if (training) {
    loss_.emplace(ctx);
    AdamConfig ac = adamConfigOf(config);
    ac.decayRate = config.learningRateFinal / config.learningRate;
    ac.decaySteps = float(config.decaySteps);
    adam_.emplace(ctx, ac);
  }
  coarse_ = makeNetwork(ctx, config.model, config.seed, training);
  if (config.model.separateFineNetwork) fine_ = makeNetwork(ctx, config.model, config.seed + 1, training);
  const uint32_t nc = config.model.coarseSamples, nf = config.model.fineSamples;
  allocateLevel(ctx, levels_[0], *coarse_.mlp, rayCapacity, nc, training);
  allocateLevel(ctx, levels_[1], *fine().mlp, rayCapacity, nc + nf, training);
  rays_ = gpu::Buffer(ctx, VkDeviceSize(rayCapacity) * kRayBytes);
  pixelIds_ = gpu::Buffer(ctx, VkDeviceSize(rayCapacity) * kPixelIdBytes);
  background_ = gpu::Buffer(ctx, VkDeviceSize(rayCapacity) * 16);
  zeroDepthGrad_ = gpu::Buffer(ctx, VkDeviceSize(rayCapacity) * 4);
  zeroDepthGrad_.zero();
  noOffsets_ = gpu::Buffer(ctx, 16);
}

void VanillaPipeline::recordLevel(gpu::Recorder& rec, LevelBuffers& l, NetworkState& net, uint32_t numRays, bool keep) {
  const uint32_t n = numRays * l.samplesPerRay;
  points_.record(rec, rays_, l.samples, numRays, l.samplesPerRay, box_, l.positions, l.directions);
  posEncoding_.record(rec, l.positions, n, l.posFeatures, net.mlp->posStride(), 0);
  dirEncoding_.record(rec, l.directions, n, l.dirFeatures, net.mlp->dirStride(), 0);
  net.mlp->recordForward(rec, n, net.params, l.posFeatures, l.dirFeatures, l.field, keep ? l.workspace.get() : nullptr);
  gpu::BufferRange bg(background_);
  compositor_.recordForward(rec, numRays, l.samplesPerRay, noOffsets_, l.samples, l.field, config_.background, &bg,
                            l.color, l.depth, l.weights);
}

void VanillaPipeline::recordForward(gpu::Recorder& rec, uint32_t numRays, uint32_t seed, bool jitter) {
  if (numRays > capacity_) throw Error("VanillaPipeline: batch of " + std::to_string(numRays) + " rays over capacity");
  LevelBuffers& c = levels_[0];
  LevelBuffers& f = levels_[1];
  stratified_.record(rec, rays_, numRays, c.samplesPerRay, seed, jitter, c.samples);
  recordLevel(rec, c, coarse_, numRays, training_);
  pdf_.record(rec, rays_, numRays, c.samples, c.weights, c.samplesPerRay, f.samplesPerRay - c.samplesPerRay,
              seed ^ 0x9e3779b9u, jitter, 1e-5f, f.samples);
  recordLevel(rec, f, fine(), numRays, training_);
}

void VanillaPipeline::recordTrainStep(gpu::Recorder& rec, uint32_t numRays, const gpu::Buffer& images,
                                      const gpu::Buffer& cameras, uint32_t step, float learningRate) {
  gpu::BufferRange bg(background_);
  for (int li = 0; li < 2; ++li) {
    LevelBuffers& l = levels_[li];
    NetworkState& net = li == 0 ? coarse_ : fine();
    const uint32_t n = numRays * l.samplesPerRay;
    loss_->record(rec, numRays, l.color, pixelIds_, images, cameras, background_, l.dColor, l.partials);
    compositor_.recordBackward(rec, numRays, l.samplesPerRay, noOffsets_, l.samples, l.field, config_.background, &bg,
                               l.dColor, zeroDepthGrad_, l.dField);
    net.mlp->recordBackward(rec, n, net.params, l.posFeatures, l.dirFeatures, l.field, l.dField, net.grads, *l.workspace);
  }
  adam_->record(rec, coarse_.params, coarse_.grads, coarse_.m, coarse_.v, uint32_t(coarse_.mlp->parameterCount()), step,
                learningRate);
  if (separateFine())
    adam_->record(rec, fine_.params, fine_.grads, fine_.m, fine_.v, uint32_t(fine_.mlp->parameterCount()), step,
                  learningRate);
}

void VanillaPipeline::recordRender(gpu::Recorder& rec, const gpu::BufferRange& cameras, uint32_t camera, uint32_t first,
                                   uint32_t count, const std::array<float, 3>& background, bool) {
  rayGen_.recordImage(rec, cameras, camera, first, count, box_, kNearPlane, rays_, pixelIds_);
  backgrounds_.recordConstant(rec, background_, count, background);
  recordForward(rec, count, 0, false);
}

FieldPipeline::StepSize VanillaPipeline::trainStep(gpu::Recorder& rec, const TrainingData& data, uint32_t step) {
  const uint32_t R = capacity_;
  const uint32_t seed = ref::pcgHash(config_.seed * 7919u + step);
  const float lr = config_.learningRate *
                   std::pow(config_.learningRateFinal / config_.learningRate, float(step) / float(config_.decaySteps));
  rec.begin();
  rayGen_.recordRandom(rec, *data.cameras, data.numCameras, seed, R, box_, kNearPlane, rays_, pixelIds_);
  if (config_.randomBackground)
    backgrounds_.recordRandom(rec, background_, R, seed);
  else
    backgrounds_.recordConstant(rec, background_, R, config_.background);
  recordForward(rec, R, seed, true);
  recordTrainStep(rec, R, *data.images, *data.cameras, step + 1, lr);
  rec.end();
  rec.submitAndWait();
  return {R, uint64_t(R) * (levels_[0].samplesPerRay + levels_[1].samplesPerRay)};
}

std::vector<StateArray> VanillaPipeline::state() {
  std::vector<StateArray> out;
  auto add = [&](const std::string& prefix, NetworkState& n) {
    const size_t count = n.mlp->parameterCount();
    out.push_back({prefix + ".params", &n.params, count, false});
    if (training_) {
      out.push_back({prefix + ".adam_m", &n.m, count, true});
      out.push_back({prefix + ".adam_v", &n.v, count, true});
    }
  };
  add("coarse", coarse_);
  if (separateFine()) add("fine", fine_);
  return out;
}

// The same keys as FastPipeline's where they mean the same, so bench.md compares them line by line.
std::vector<std::pair<std::string, double>> VanillaPipeline::statistics() {
  VkDeviceSize bytes = 0;
  auto add = [&](const gpu::Buffer& b) { bytes += b.valid() ? b.size() : 0; };
  for (const NetworkState* n : {&coarse_, &fine_})
    for (const gpu::Buffer* b : {&n->params, &n->grads, &n->m, &n->v}) add(*b);
  for (const LevelBuffers& l : levels_)
    for (const gpu::Buffer* b : {&l.samples, &l.positions, &l.directions, &l.posFeatures, &l.dirFeatures, &l.field,
                                 &l.color, &l.depth, &l.weights, &l.dField, &l.dColor, &l.partials})
      add(*b);
  for (const gpu::Buffer* b : {&rays_, &pixelIds_, &background_, &zeroDepthGrad_, &noOffsets_}) add(*b);
  const double fineParams = separateFine() ? double(fine_.mlp->parameterCount()) : 0.0;
  return {{"samples per ray (MLP queries: coarse + fine)", double(levels_[0].samplesPerRay + levels_[1].samplesPerRay)},
          {"rays per step", double(config_.raysPerBatch)},
          {"parameters (MLP)", double(coarse_.mlp->parameterCount()) + fineParams},
          {"device buffers MiB (excl. MLP workspace)", double(bytes) / (1 << 20)}};
}

}  // namespace vknerf::nerf

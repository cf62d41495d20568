#include "models/vanilla/vanilla_pipeline.h"

#include "vknerf/error.h"

namespace vknerf::models {

namespace {

VanillaModel withOverrides(VanillaModel m, const RenderSettings& overrides) {
  if (overrides.coarseSamples) m.coarseSamples = overrides.coarseSamples;
  if (overrides.fineSamples) m.fineSamples = overrides.fineSamples;
  return m;
}

}  // namespace

Network::Network(Context& ctx, const VanillaModel& m, uint32_t seed, const std::string& name,
                 const std::optional<nerf::AdamConfig>& adam)
    : mlp(ctx, nerf::MlpConfig{.depth = m.depth,
                         .width = m.width,
                         .skipLayer = m.skipLayer,
                         .posDims = 3 + 6 * m.posLevels,
                         .dirDims = 3 + 6 * m.dirLevels,
                         .density = m.density,
                         .seed = seed}),
      parameters(ctx, name, mlp.initialParameters(), adam) {}

Level::Level(Context& ctx, const nerf::NerfMlp& mlp, uint32_t rays, uint32_t spr, bool training)
    : samplesPerRay(spr),
      samples(ctx, VkDeviceSize(rays) * spr * nerf::kSampleBytes, "the samples along the rays"),
      weights(ctx, VkDeviceSize(rays) * spr * sizeof(float), "the compositing weights"),
      color(ctx, VkDeviceSize(rays) * 16, "the rendered colours"),
      depth(ctx, VkDeviceSize(rays) * sizeof(float), "the rendered depths"),
      field(ctx, mlp, rays * spr, training) {
  if (!training) return;
  dColor = gpu::Buffer(ctx, VkDeviceSize(rays) * 16);
}

VanillaPipeline::VanillaPipeline(Context& ctx, const TrainConfig& config, const Aabb& box, uint32_t rayCapacity,
                                 bool training, const RenderSettings& overrides)
    : FieldPipeline(ctx, rayCapacity, training),
      config_(config),
      model_(withOverrides(config.vanillaModel(), overrides)),
      box_(box),
      training_(training),
      rays_(ctx, rayCapacity),
      stratified_(ctx),
      pdf_(ctx),
      points_(ctx),
      posEncoding_(ctx, 3, model_.posLevels, true),
      dirEncoding_(ctx, 3, model_.dirLevels, true),
      compositor_(ctx),
      adam_(training ? std::optional(adamConfigOf(config)) : std::nullopt),
      coarse_(ctx, model_, config.seed, "coarse", adam_),
      fine_(model_.separateFineNetwork ? std::make_unique<Network>(ctx, model_, config.seed + 1, "fine", adam_)
                                       : nullptr),
      levels_{{ctx, coarse_.mlp, rayCapacity, model_.coarseSamples, training},
              {ctx, fine().mlp, rayCapacity, model_.coarseSamples + model_.fineSamples, training}},
      zeroDepthGrad_(gpu::Buffer::zeros(ctx, VkDeviceSize(rayCapacity) * sizeof(float))) {
  if (training) {
    loss_.emplace(ctx);
    coarsePartials_ = gpu::Buffer(ctx, gpu::groupsFor(rayCapacity, nerf::PhotometricLoss::kRaysPerPartial) * sizeof(float));
  }
  parts().add(coarse_.parameters, ParameterRole::Network);
  if (fine_) parts().add(fine_->parameters, ParameterRole::Network);
}

void VanillaPipeline::recordNetwork(gpu::Recorder& rec, FieldBatch& f, Network& net, uint32_t n, bool keep) {
  posEncoding_.recordForward(rec, {n, f.positions, f.posFeatures, net.mlp.posStride(), 0});
  dirEncoding_.recordForward(rec, {n, f.directions, f.dirFeatures, net.mlp.dirStride(), 0});
  net.mlp.recordForward(rec, f.mlpRows(n), net.parameters.params(), keep ? f.workspace.get() : nullptr);
}

// The fine level's network, as the render's second pass queries it.
void VanillaPipeline::recordQuery(gpu::Recorder& rec, uint32_t count) {
  recordNetwork(rec, levels_[1].field, fine(), count, false);
}

void VanillaPipeline::recordLevel(gpu::Recorder& rec, Level& l, Network& net, uint32_t numRays, bool keep) {
  const uint32_t n = numRays * l.samplesPerRay;
  FieldBatch& f = l.field;
  points_.record(rec, {rays_.rays(), numRays}, l.samples, l.samplesPerRay, box_, {f.positions, f.directions});
  recordNetwork(rec, f, net, n, keep);
  compositor_.recordForward(rec, compositeInputs(l, numRays), {l.color, l.depth, l.weights});
}

nerf::CompositeInputs VanillaPipeline::compositeInputs(const Level& l, uint32_t numRays) {
  return {.numRays = numRays,
          .samplesPerRay = l.samplesPerRay,
          .samples = l.samples,
          .field = l.field.field,
          .background = config_.background,
          .perRayBackground = gpu::BufferRange(rays_.background())};
}

void VanillaPipeline::recordForward(gpu::Recorder& rec, uint32_t numRays, uint32_t seed, bool jitter) {
  if (numRays > rayCapacity()) throw Error("VanillaPipeline: batch of " + std::to_string(numRays) + " rays over capacity");
  Level& c = levels_[0];
  Level& f = levels_[1];
  const nerf::RaySpan rays{rays_.rays(), numRays};
  stratified_.record(rec, rays, c.samplesPerRay, {seed, jitter}, c.samples);
  recordLevel(rec, c, coarse_, numRays, training_);
  pdf_.record(rec, rays, {c.samples, c.weights, c.samplesPerRay},
              {f.samplesPerRay - c.samplesPerRay, {seed ^ 0x9e3779b9u, jitter}, 1e-5f}, f.samples);
  recordLevel(rec, f, fine(), numRays, training_);
}

void VanillaPipeline::recordBackward(gpu::Recorder& rec, uint32_t numRays, const TrainingData& data, nerf::OptimizerStep at) {
  for (int li = 0; li < 2; ++li) {
    Level& l = levels_[li];
    Network& net = li == 0 ? coarse_ : fine();
    FieldBatch& f = l.field;
    // The fine level's loss is the one reported.
    const gpu::BufferRange partials = li == 1 ? report().photometricPartials() : gpu::BufferRange(coarsePartials_);
    loss_->record(rec, {numRays, l.color, rays_.pixelIds(), rays_.background()}, {data.pixels, *data.cameras},
                  {l.dColor, partials});
    compositor_.recordBackward(rec, compositeInputs(l, numRays), {l.dColor, zeroDepthGrad_, f.dField});
    net.mlp.recordBackward(rec, f.mlpRows(numRays * l.samplesPerRay), net.parameters.params(),
                           {f.dField, net.parameters.grads()}, *f.workspace);
  }
  parts().recordOptimizerSteps(rec, at);
}

void VanillaPipeline::doRecordRender(gpu::Recorder& rec, const ViewBlock& view, bool mayWait) {
  rays_.recordView(rec, view, box_);
  recordForward(rec, view.count, 0, false);
  if (mayWait) countRenderedSamples(uint64_t(view.count) * (levels_[0].samplesPerRay + levels_[1].samplesPerRay));
}

uint32_t VanillaPipeline::doRecordTrainStep(gpu::Recorder& rec, const TrainingData& data, nerf::OptimizerStep at) {
  if (!training_) throw Error("vanilla model: pipeline was not built for training");
  const uint32_t step = at.step;
  const uint32_t R = rayCapacity();
  const uint32_t seed = stepSeed(config_, step);
  rays_.recordTraining(rec, data, seed, R, box_, config_);
  recordForward(rec, R, seed, true);
  recordBackward(rec, R, data, at);
  return R;
}

// The batch is the same every step: nothing to read back.
FieldPipeline::StepSize VanillaPipeline::doCollectTrainStep(uint32_t) {
  return {rayCapacity(), uint64_t(rayCapacity()) * (levels_[0].samplesPerRay + levels_[1].samplesPerRay)};
}

ModelStatistics VanillaPipeline::modelStatistics() {
  ModelStatistics s;
  s.mlpParameters = parts().parameterCount(ParameterRole::Network);
  s.samplesPerRay = double(levels_[0].samplesPerRay + levels_[1].samplesPerRay);
  s.raysPerStep = rayCapacity();
  s.samplesPerStep = uint64_t(rayCapacity()) * (levels_[0].samplesPerRay + levels_[1].samplesPerRay);
  return s;
}

}  // namespace vknerf::models

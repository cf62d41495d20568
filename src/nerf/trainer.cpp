#include "vknerf/trainer.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

#include "gpu/recorder.h"
#include "nerf/checkpoint.h"
#include "nerf/vanilla_pipeline.h"
#include "reference/rng.h"
#include "vknerf/error.h"

namespace vknerf {

using nlohmann::json;

namespace {

constexpr float kNearPlane = 0.05f;
constexpr uint32_t kRenderRays = 4096;

json toJson(const TrainConfig& c) {
  const ModelConfig& m = c.model;
  return {{"model", {{"name", m.name}, {"width", m.width}, {"depth", m.depth}, {"skip_layer", m.skipLayer},
                     {"pos_levels", m.posLevels}, {"dir_levels", m.dirLevels}, {"density", uint32_t(m.density)},
                     {"coarse_samples", m.coarseSamples}, {"fine_samples", m.fineSamples},
                     {"separate_fine", m.separateFineNetwork}}},
          {"rays_per_batch", c.raysPerBatch}, {"lr", c.learningRate}, {"lr_final", c.learningRateFinal},
          {"decay_steps", c.decaySteps}, {"beta1", c.beta1}, {"beta2", c.beta2}, {"epsilon", c.epsilon},
          {"random_background", c.randomBackground}, {"background", c.background}, {"seed", c.seed}};
}

TrainConfig fromJson(const json& j, const std::string& file) {
  try {
    TrainConfig c;
    const json& m = j.at("model");
    c.model.name = m.at("name");
    c.model.width = m.at("width");
    c.model.depth = m.at("depth");
    c.model.skipLayer = m.at("skip_layer");
    c.model.posLevels = m.at("pos_levels");
    c.model.dirLevels = m.at("dir_levels");
    c.model.density = DensityActivation(m.at("density").get<uint32_t>());
    c.model.coarseSamples = m.at("coarse_samples");
    c.model.fineSamples = m.at("fine_samples");
    c.model.separateFineNetwork = m.at("separate_fine");
    c.raysPerBatch = j.at("rays_per_batch");
    c.learningRate = j.at("lr");
    c.learningRateFinal = j.at("lr_final");
    c.decaySteps = j.at("decay_steps");
    c.beta1 = j.at("beta1");
    c.beta2 = j.at("beta2");
    c.epsilon = j.at("epsilon");
    c.randomBackground = j.at("random_background");
    c.background = j.at("background");
    c.seed = j.at("seed");
    return c;
  } catch (const json::exception& e) {
    throw Error(file + ": checkpoint config: " + e.what());
  }
}

json configJson(const nerf::Checkpoint& ck, const std::string& path) {
  try {
    return json::parse(ck.config);
  } catch (const json::exception& e) {
    throw Error(path + ": checkpoint config is not valid JSON: " + e.what());
  }
}

}  // namespace

// ---------------------------------------------------------------- Model

struct Model::Impl {
  std::shared_ptr<Context> ctx;
  TrainConfig config;
  Aabb box;
  std::unique_ptr<nerf::VanillaPipeline> own;  // a loaded model's inference pipeline
  nerf::VanillaPipeline* pipe = nullptr;       // own, or the trainer's

  RenderedImage render(const Camera& cam) const {
    if (cam.width == 0 || cam.height == 0) throw Error("render: camera has an empty image size");
    if (!(cam.fx > 0) || !(cam.fy > 0)) throw Error("render: camera focal length must be positive");
    Context& c = *ctx;
    auto packed = nerf::packCameras(std::span<const Camera>(&cam, 1));
    auto camBuf = gpu::Buffer::of(c, packed);
    const uint32_t total = cam.width * cam.height, cap = pipe->rayCapacity();
    RenderedImage img;
    img.width = cam.width;
    img.height = cam.height;
    img.rgb.resize(size_t(total) * 3);
    img.depth.resize(total);
    img.opacity.resize(total);
    gpu::Recorder rec(c);
    for (uint32_t first = 0; first < total; first += cap) {
      const uint32_t n = std::min(cap, total - first);
      rec.begin();
      pipe->rayGeneration().recordImage(rec, camBuf, 0, first, n, box, kNearPlane, pipe->rays(), pipe->pixelIds());
      pipe->backgroundColors().recordConstant(rec, pipe->background(), n, config.background);
      pipe->recordForward(rec, n, 0, false);
      rec.end();
      rec.submitAndWait();
      auto color = pipe->fineLevel().color.download<float>(size_t(n) * 4);
      auto depth = pipe->fineLevel().depth.download<float>(n);
      for (uint32_t i = 0; i < n; ++i) {
        const size_t p = first + i;
        for (int k = 0; k < 3; ++k) img.rgb[p * 3 + k] = color[i * 4 + k];
        const float o = color[i * 4 + 3];
        img.opacity[p] = o;
        img.depth[p] = o > 1e-4f ? depth[i] / o : 0.0f;
      }
    }
    return img;
  }
};

Model::Model(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Model::~Model() = default;
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;
const TrainConfig& Model::config() const { return impl_->config; }
const Aabb& Model::bounds() const { return impl_->box; }
RenderedImage Model::render(const Camera& camera) const { return impl_->render(camera); }

namespace {

Aabb boxFromJson(const json& j) {
  Aabb b;
  b.min = j.at("min").get<std::array<float, 3>>();
  b.max = j.at("max").get<std::array<float, 3>>();
  return b;
}

void uploadChecked(const nerf::Checkpoint& ck, const std::string& name, gpu::Buffer& dst, size_t count) {
  dst.upload(ck.get<float>(name, count));
}

}  // namespace

Model Model::load(std::shared_ptr<Context> ctx, const std::string& path) {
  auto ck = nerf::Checkpoint::load(path);
  json j = configJson(ck, path);
  auto impl = std::make_unique<Impl>();
  impl->ctx = ctx;
  impl->config = fromJson(j.at("config"), path);
  try {
    impl->box = boxFromJson(j.at("bounds"));
  } catch (const json::exception& e) {
    throw Error(path + ": checkpoint bounds: " + e.what());
  }
  impl->own = std::make_unique<nerf::VanillaPipeline>(*ctx, impl->config, impl->box, kRenderRays, false);
  impl->pipe = impl->own.get();
  auto& p = *impl->pipe;
  uploadChecked(ck, "coarse.params", p.coarse().params, p.coarse().mlp->parameterCount());
  if (p.separateFine()) uploadChecked(ck, "fine.params", p.fine().params, p.fine().mlp->parameterCount());
  return Model(std::move(impl));
}

// ---------------------------------------------------------------- Trainer

struct Trainer::Impl {
  std::shared_ptr<Context> ctx;
  TrainConfig config;
  Aabb box;
  uint32_t numCameras = 0;
  gpu::Buffer images, cameras;
  std::unique_ptr<nerf::VanillaPipeline> pipe;
  std::unique_ptr<gpu::Recorder> rec;
  std::unique_ptr<Model> model;
  uint32_t step = 0;
};

Trainer::Trainer(std::shared_ptr<Context> ctx, const Dataset& train, const TrainConfig& config)
    : impl_(std::make_unique<Impl>()) {
  if (train.cameras.empty()) throw Error("training set is empty");
  if (train.images.size() != train.cameras.size()) throw Error("training set has " + std::to_string(train.images.size()) +
                                                              " images for " + std::to_string(train.cameras.size()) + " cameras");
  auto& s = *impl_;
  s.ctx = ctx;
  s.config = config;
  s.box = train.bounds;
  s.numCameras = uint32_t(train.cameras.size());
  std::vector<uint8_t> pixels;
  for (const auto& im : train.images) pixels.insert(pixels.end(), im.rgba.begin(), im.rgba.end());
  s.images = gpu::Buffer::of(*ctx, pixels);
  s.cameras = gpu::Buffer::of(*ctx, nerf::packCameras(train.cameras));
  s.pipe = std::make_unique<nerf::VanillaPipeline>(*ctx, config, s.box, config.raysPerBatch, true);
  s.rec = std::make_unique<gpu::Recorder>(*ctx, true);
  auto m = std::make_unique<Model::Impl>();
  m->ctx = ctx;
  m->config = config;
  m->box = s.box;
  m->pipe = s.pipe.get();
  s.model.reset(new Model(std::move(m)));
}

Trainer::~Trainer() = default;
uint32_t Trainer::steps() const { return impl_->step; }
std::vector<std::pair<std::string, double>> Trainer::lastStepTimings() const { return impl_->rec->timings(); }
const Model& Trainer::model() const { return *impl_->model; }

StepStats Trainer::step(bool readLoss) {
  auto& s = *impl_;
  auto& p = *s.pipe;
  const uint32_t R = s.config.raysPerBatch;
  const uint32_t seed = ref::pcgHash(s.config.seed * 7919u + s.step);
  const float lr = s.config.learningRate *
                   std::pow(s.config.learningRateFinal / s.config.learningRate, float(s.step) / float(s.config.decaySteps));
  gpu::Recorder& rec = *s.rec;
  rec.begin();
  p.rayGeneration().recordRandom(rec, s.cameras, s.numCameras, seed, R, s.box, kNearPlane, p.rays(), p.pixelIds());
  if (s.config.randomBackground)
    p.backgroundColors().recordRandom(rec, p.background(), R, seed);
  else
    p.backgroundColors().recordConstant(rec, p.background(), R, s.config.background);
  p.recordForward(rec, R, seed, true);
  p.recordTrainStep(rec, R, s.images, s.cameras, s.step + 1, lr);
  rec.end();
  rec.submitAndWait();
  ++s.step;
  StepStats st;
  st.step = s.step;
  if (readLoss) {
    auto stats = nerf::PhotometricLoss::summarize(
        p.fineLevel().partials.download<float>(p.fineLevel().partials.size() / 4), R);
    st.hasLoss = true;
    st.loss = stats.mse;
    st.psnr = stats.psnr;
    if (!std::isfinite(st.loss)) throw Error("training diverged: loss is " + std::to_string(st.loss) + " at step " + std::to_string(s.step));
  }
  return st;
}

void Trainer::save(const std::string& path) const {
  auto& s = *impl_;
  auto& p = *s.pipe;
  nerf::Checkpoint ck;
  json j = {{"format", "vknerf"}, {"config", toJson(s.config)}, {"step", s.step},
            {"bounds", {{"min", s.box.min}, {"max", s.box.max}}}};
  ck.config = j.dump(2);
  auto put = [&](const std::string& prefix, const nerf::NetworkState& n) {
    const size_t count = n.mlp->parameterCount();
    ck.put(prefix + ".params", n.params.download<float>(count));
    ck.put(prefix + ".adam_m", n.m.download<float>(count));
    ck.put(prefix + ".adam_v", n.v.download<float>(count));
  };
  put("coarse", p.coarse());
  if (p.separateFine()) put("fine", p.fine());
  ck.save(path);
}

TrainConfig Trainer::configOf(const std::string& path) {
  auto ck = nerf::Checkpoint::load(path);
  try {
    return fromJson(configJson(ck, path).at("config"), path);
  } catch (const json::exception& e) {
    throw Error(path + ": checkpoint config: " + e.what());
  }
}

void Trainer::resume(const std::string& path) {
  auto& s = *impl_;
  auto& p = *s.pipe;
  auto ck = nerf::Checkpoint::load(path);
  json j = configJson(ck, path);
  TrainConfig saved = fromJson(j.at("config"), path);
  if (toJson(saved)["model"] != toJson(s.config)["model"])
    throw Error(path + ": checkpoint model config differs from this run's (" + saved.describe() + ")");
  auto load = [&](const std::string& prefix, nerf::NetworkState& n) {
    const size_t count = n.mlp->parameterCount();
    uploadChecked(ck, prefix + ".params", n.params, count);
    uploadChecked(ck, prefix + ".adam_m", n.m, count);
    uploadChecked(ck, prefix + ".adam_v", n.v, count);
  };
  load("coarse", p.coarse());
  if (p.separateFine()) load("fine", p.fine());
  s.step = j.at("step");
}

}  // namespace vknerf

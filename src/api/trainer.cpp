#include "vknerf/trainer.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>

#include "gpu/recorder.h"
#include "io/checkpoint/checkpoint.h"
#include "io/checkpoint/config_json.h"
#include "io/dataset/memory_fit.h"
#include "api/fast_capacity.h"
#include "api/model_impl.h"
#include "nerf/loss/photometric_loss.h"
#include "nerf/loss/pixel_bindings.h"
#include "nerf/rays/rays.h"
#include "reference/rng.h"
#include "vknerf/checkpoint_scene.h"
#include "vknerf/error.h"

namespace vknerf {

using nlohmann::json;
using nerf::toJson;

namespace {

TrainConfig fromJson(const json& j, const std::string& file) { return nerf::trainConfigFromJson(j, file); }

// instant-ngp's cascades for an aabb_scale: enough doublings of the inner cube to reach the box.
uint32_t cascadesFor(float aabbScale) {
  uint32_t c = 1;
  constexpr uint32_t kMaxCascades = 8;  // as TrainConfig::validate allows
  while (c < kMaxCascades && std::ldexp(1.0f, int(c - 1)) < aabbScale) ++c;
  return c;
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

RenderedImage Model::Impl::render(const Camera& cam, const std::function<void(uint64_t, uint64_t)>& progress) const {
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
  img.background.resize(size_t(total) * 3);
  gpu::Recorder rec(c);
  for (uint32_t first = 0; first < total; first += cap) {
    const uint32_t n = std::min(cap, total - first);
    rec.begin();
    pipe->recordRender(rec, camBuf, 0, first, n, config.background, true);
    rec.end();
    rec.submitAndWait();
    auto color = pipe->color().download<float>(size_t(n) * 4);
    auto depth = pipe->depth().download<float>(n);
    auto background = pipe->backgrounds().download<float>(size_t(n) * 4);
    for (uint32_t i = 0; i < n; ++i) {
      const size_t p = first + i;
      for (int k = 0; k < 3; ++k) img.rgb[p * 3 + k] = color[i * 4 + k], img.background[p * 3 + k] = background[i * 4 + k];
      const float o = color[i * 4 + 3];
      img.opacity[p] = o;
      img.depth[p] = o > 1e-4f ? depth[i] / o : 0.0f;
    }
    if (progress) progress(first + n, total);
  }
  return img;
}

Model::Model(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Model::~Model() = default;
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;
const TrainConfig& Model::config() const { return impl_->config; }
const Aabb& Model::bounds() const { return impl_->box; }
RenderedImage Model::render(const Camera& camera, const std::function<void(uint64_t, uint64_t)>& progress) const {
  return impl_->render(camera, progress);
}

namespace {

Aabb boxFromJson(const json& j) {
  Aabb b;
  b.min = j.at("min").get<std::array<float, 3>>();
  b.max = j.at("max").get<std::array<float, 3>>();
  return b;
}

// A checksum proves the bytes are as written, not that they are a model: a NaN or infinite
// parameter would render as garbage (or crash the depth writer) without a word.
void uploadChecked(const nerf::Checkpoint& ck, const nerf::StateArray& a) {
  auto values = ck.get<float>(a.name, a.count);
  for (size_t i = 0; a.numbers && i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw Error(ck.path + ": checkpoint section '" + a.name + "' holds a non-finite value at index " + std::to_string(i));
  a.buffer->upload(values);
}

// The checkpoint's scene box, within `tolerance` of its extent (at least 1) of `box`.
bool sameBox(const Aabb& a, const Aabb& b, float tolerance) {
  for (int k = 0; k < 3; ++k) {
    const float tol = tolerance * std::max(1.0f, std::fabs(a.max[k] - a.min[k]));
    if (!(std::fabs(a.min[k] - b.min[k]) <= tol) || !(std::fabs(a.max[k] - b.max[k]) <= tol)) return false;
  }
  return true;
}

std::string boxText(const Aabb& b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "[%g %g %g]..[%g %g %g]", b.min[0], b.min[1], b.min[2], b.max[0], b.max[1], b.max[2]);
  return buf;
}

// What a scene shows of itself for the checks against a checkpoint's record of its own.
struct SceneFacts {
  Aabb box;
  float boxTolerance = 1e-4f;  // float printing precision
  std::optional<uint32_t> cameras;                          // the training split's camera count
  std::optional<std::pair<uint32_t, uint32_t>> imageSize;  // its first image's size
};

// Weights fitted to another scene would train or render inside this scene's box: the checkpoint at
// `path` (its JSON record `j`) must have been trained on the scene `scene` describes.
void checkSceneRecord(const std::string& path, const json& j, const SceneFacts& scene) {
  try {
    const Aabb saved = boxFromJson(j.at("bounds"));
    if (!sameBox(saved, scene.box, scene.boxTolerance))
      throw Error(path + ": checkpoint scene box " + boxText(saved) + " differs from this dataset's " +
                  boxText(scene.box) + "; it was trained on another scene");
    if (!j.contains("scene") || !scene.cameras) return;  // checkpoints written before the scene record have the box alone
    const json& sc = j.at("scene");
    const uint32_t n = sc.at("cameras"), w = sc.at("width"), h = sc.at("height");
    if (!scene.imageSize && n != *scene.cameras)
      throw Error(path + ": checkpoint was trained on " + std::to_string(n) + " images, this dataset's training split has " +
                  std::to_string(*scene.cameras) + "; it was trained on another scene");
    if (scene.imageSize && (n != *scene.cameras || w != scene.imageSize->first || h != scene.imageSize->second))
      throw Error(path + ": checkpoint was trained on " + std::to_string(n) + " images of " + std::to_string(w) + "x" +
                  std::to_string(h) + ", this dataset has " + std::to_string(*scene.cameras) + " of " +
                  std::to_string(scene.imageSize->first) + "x" + std::to_string(scene.imageSize->second) +
                  "; it was trained on another scene or --downscale");
  } catch (const json::exception& e) {
    throw Error(path + ": checkpoint scene record: " + e.what());
  }
}

}  // namespace

Model Model::load(std::shared_ptr<Context> ctx, const std::string& path, const RenderSettings& settings) {
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
  impl->own = nerf::makeFieldPipeline(*ctx, impl->config, impl->box, nerf::kRenderRays, false, settings);
  impl->pipe = impl->own.get();
  for (auto& a : impl->pipe->state()) uploadChecked(ck, a);
  impl->pipe->stateLoaded();
  return Model(std::move(impl));
}

// ---------------------------------------------------------------- Trainer

struct Trainer::Impl {
  std::shared_ptr<Context> ctx;
  TrainConfig config;
  Aabb box;
  uint32_t numCameras = 0, imageWidth = 0, imageHeight = 0;  // the first image's size, for the checkpoint
  std::unique_ptr<nerf::TrainingPixels> pixels;
  gpu::Buffer cameras;
  bool transparentPixels = false;  // some training pixel has alpha < 255
  std::unique_ptr<nerf::FieldPipeline> pipe;
  uint32_t lastRays = 0;
  std::chrono::steady_clock::time_point stepStart;
  double lastStepHostAfterMs = 0, lastStepWallMs = 0;  // the rest is in rec's submission log
  std::unique_ptr<gpu::Recorder> rec;
  std::unique_ptr<Model> model;
  uint32_t step = 0;
  std::string capacityNote;
};

Trainer::Trainer(std::shared_ptr<Context> ctx, const Dataset& train, const TrainConfig& config)
    : Trainer(std::move(ctx), train, config, nullptr) {}

Trainer::Trainer(std::shared_ptr<Context> ctx, Dataset&& train, const TrainConfig& config)
    : Trainer(std::move(ctx), train, config, &train) {}

Trainer::Trainer(std::shared_ptr<Context> ctx, const Dataset& train, const TrainConfig& config, Dataset* release)
    : impl_(std::make_unique<Impl>()) {
  if (train.cameras.empty()) throw Error("training set is empty");
  if (train.images.size() != train.cameras.size()) throw Error("training set has " + std::to_string(train.images.size()) +
                                                              " images for " + std::to_string(train.cameras.size()) + " cameras");
  auto& s = *impl_;
  s.ctx = ctx;
  s.config = config;
  if (s.config.isFast() && s.config.fastModel().cascades == 0) s.config.fastModel().cascades = cascadesFor(train.aabbScale);
  if (s.config.isFast()) s.capacityNote = nerf::resolveFastCapacity(s.config.fastModel(), train, ctx->isCpu());
  s.box = train.bounds;
  s.numCameras = uint32_t(train.cameras.size());
  s.imageWidth = train.images[0].width;
  s.imageHeight = train.images[0].height;
  std::vector<nerf::ImageSize> sizes;
  std::vector<uint64_t> pixelCounts;
  for (uint32_t i = 0; i < s.numCameras; ++i) {
    const ImageRGBA8& im = train.images[i];
    if (im.width != train.cameras[i].width || im.height != train.cameras[i].height ||
        im.rgba.size() != size_t(im.width) * im.height * 4)
      throw Error("training image " + std::to_string(i) + " is " + std::to_string(im.width) + "x" +
                  std::to_string(im.height) + " with " + std::to_string(im.rgba.size()) + " bytes but its camera is " +
                  std::to_string(train.cameras[i].width) + "x" + std::to_string(train.cameras[i].height));
    for (size_t k = 3; k < im.rgba.size() && !s.transparentPixels; k += 4) s.transparentPixels = im.rgba[k] != 255;
    sizes.emplace_back(im.width, im.height);
    pixelCounts.push_back(uint64_t(im.width) * im.height);
  }
  // Photos without alpha leave what lies behind the scene box to the model: a learned far field.
  if (s.config.isFast() && s.config.fastModel().farField == FarField::Auto) {
    s.config.fastModel().farField = s.transparentPixels ? FarField::Constant : FarField::Learned;
    s.capacityNote += std::string(s.capacityNote.empty() ? "" : "\n") + "far field: " +
                      (s.transparentPixels ? "constant (the photos have alpha)" : "learned (the photos have no alpha)");
  }
  // Where a photo is transparent its target is composited over the background: a learned one would
  // be fitted to itself there.
  if (s.config.isFast() && s.config.fastModel().farField == FarField::Learned && s.transparentPixels)
    throw Error("model.far_field learned needs opaque photos, and some training pixel has alpha < 255 "
                "(use the far field auto or constant)");
  // The fit is checked before the pixels are allocated: the pixels alone first, then with the
  // model's buffers, which are measured by building the model (its size follows the configuration,
  // not the dataset).
  const uint64_t deviceBytes = nerf::deviceMemoryBytes(*ctx);
  const std::string device = "the device (" + ctx->deviceName() + ")";
  nerf::requireFit("training", sizes, 0, "", deviceBytes, device);
  auto layout = nerf::planPixelBindings(pixelCounts, nerf::pixelBytesPerBinding(*ctx));
  s.pipe = nerf::makeFieldPipeline(*ctx, s.config, s.box, s.config.raysPerBatch, true);
  nerf::requireFit("training", sizes, s.pipe->memory()->bytes(), "model", deviceBytes, device);
  // On a CPU device the device's memory is the host's: the pixels come out of what is left of it.
  if (ctx->isCpu()) nerf::requireFit("training", sizes, 0, "", nerf::availableHostBytes(), "host memory (available)");
  s.pixels = std::make_unique<nerf::TrainingPixels>(*ctx, layout);
  for (uint32_t i = 0; i < s.numCameras; ++i) {
    s.pixels->upload(i, train.images[i].rgba.data());
    if (release) std::vector<uint8_t>().swap(release->images[i].rgba);
  }
  s.cameras = gpu::Buffer::of(*ctx, nerf::packCameras(train.cameras, layout.images));
  s.pipe->markUnseenEmpty(train.cameras);
  s.rec = std::make_unique<gpu::Recorder>(*ctx, true);
  auto m = std::make_unique<Model::Impl>();
  m->ctx = ctx;
  m->config = s.config;
  m->box = s.box;
  m->pipe = s.pipe.get();
  s.model.reset(new Model(std::move(m)));
}

Trainer::~Trainer() = default;
uint32_t Trainer::steps() const { return impl_->step; }
std::vector<std::pair<std::string, double>> Trainer::lastStepTimings() const {
  std::vector<std::pair<std::string, double>> all;
  for (const auto& sub : impl_->rec->submissions()) all.insert(all.end(), sub.kernels.begin(), sub.kernels.end());
  return all;
}

StepProfile Trainer::lastStepProfile() const {
  StepProfile p;
  for (const auto& sub : impl_->rec->submissions()) p.submissions.push_back({sub.hostBeforeMs, sub.waitMs, sub.kernels});
  p.hostAfterMs = impl_->lastStepHostAfterMs;
  p.wallMs = impl_->lastStepWallMs;
  return p;
}
const Model& Trainer::model() const { return *impl_->model; }

StepStats Trainer::step(bool readLoss) {
  auto& s = *impl_;
  s.rec->startLog();
  s.stepStart = std::chrono::steady_clock::now();
  const auto size = s.pipe->trainStep(*s.rec, {s.pixels->bindings(), &s.cameras, s.numCameras, s.transparentPixels}, s.step);
  const uint32_t R = size.rays;
  ++s.step;
  StepStats st;
  st.step = s.step;
  st.rays = R;
  st.samples = size.samples;
  if (readLoss) {
    auto stats = nerf::PhotometricLoss::summarize(
        s.pipe->lossPartials().download<float>(gpu::groupsFor(R, nerf::PhotometricLoss::kRaysPerPartial)), R);
    st.hasLoss = true;
    st.loss = stats.mse;
    st.psnr = stats.psnr;
    if (!std::isfinite(st.loss)) throw Error("training diverged: loss is " + std::to_string(st.loss) + " at step " + std::to_string(s.step));
  }
  s.lastStepHostAfterMs = s.rec->msSinceLastWait();
  s.lastStepWallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - s.stepStart).count();
  return st;
}

ModelStatistics Trainer::statistics() const { return impl_->pipe->statistics(); }
double Trainer::trainingPixelsDeviceMiB() const { return double(impl_->pixels->bytes()) / double(1 << 20); }
uint32_t Trainer::trainingPixelBindings() const { return uint32_t(impl_->pixels->bindings().size()); }
const std::string& Trainer::capacityNote() const { return impl_->capacityNote; }

void Trainer::save(const std::string& path) const {
  auto& s = *impl_;
  nerf::Checkpoint ck;
  json j = {{"format", "vknerf"}, {"config", toJson(s.config)}, {"step", s.step},
            {"bounds", {{"min", s.box.min}, {"max", s.box.max}}},
            {"scene", {{"cameras", s.numCameras}, {"width", s.imageWidth}, {"height", s.imageHeight}}}};
  ck.config = j.dump(2);
  for (auto& a : s.pipe->state()) ck.put(a.name, a.buffer->download<float>(a.count));
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
  auto ck = nerf::Checkpoint::load(path);
  json j = configJson(ck, path);
  TrainConfig saved = fromJson(j.at("config"), path);
  if (toJson(saved)["model"] != toJson(s.config)["model"])
    throw Error(path + ": checkpoint model config differs from this run's (" + saved.describe() + ")");
  SceneFacts scene;
  scene.box = s.box;
  scene.cameras = s.numCameras;
  scene.imageSize = {s.imageWidth, s.imageHeight};
  checkSceneRecord(path, j, scene);
  for (auto& a : s.pipe->state()) uploadChecked(ck, a);
  s.pipe->stateLoaded();
  s.step = j.at("step");
}

void checkTrainedOn(const std::string& checkpoint, const Dataset& scene, const DatasetOptions& options) {
  auto ck = nerf::Checkpoint::load(checkpoint);
  SceneFacts facts;
  facts.box = scene.bounds;
  // A box carved from the alpha masks moves with the resolution and split the masks are read at
  // (by 6% of the sample scene's height between --downscale 1 and 8): a tenth of its extent.
  if (scene.boundsSource == "cameras+alpha") facts.boxTolerance = 0.1f;
  if (options.split == "train") facts.cameras = uint32_t(scene.cameras.size());
  checkSceneRecord(checkpoint, configJson(ck, checkpoint), facts);
}

}  // namespace vknerf

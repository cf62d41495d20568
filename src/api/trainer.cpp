// Trainer: the training set on the device, one optimisation step at a time, and the checkpoint
// it saves and resumes from (its JSON record: io/checkpoint/checkpoint_record.h).
#include "vknerf/trainer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <optional>
#include <utility>

#include "api/model_impl.h"
#include "gpu/dispatch/recorder.h"
#include "io/checkpoint/checkpoint.h"
#include "io/checkpoint/checkpoint_record.h"
#include "io/dataset/memory_fit.h"
#include "models/common/trainable_parameters.h"
#include "models/fast/fast_choices.h"
#include "nerf/loss/photometric_loss.h"
#include "nerf/loss/pixel_bindings.h"
#include "nerf/rays/rays.h"
#include "core/camera/pose_algebra.h"
#include "vknerf/error.h"

namespace vknerf {

struct Trainer::Impl {
  std::shared_ptr<Context> ctx;
  TrainConfig config;
  Aabb box;
  uint32_t numCameras = 0, imageWidth = 0, imageHeight = 0;  // the first image's size, for the checkpoint
  std::vector<Camera> trainCameras;  // as the dataset gave them, for the checkpoint's record
  std::vector<std::string> names;    // Dataset::names, one per camera ("" where it named none)
  std::unique_ptr<nerf::TrainingPixels> pixels;
  gpu::Buffer cameras;
  bool transparentPixels = false;  // some training pixel has alpha < 255
  std::unique_ptr<models::FieldPipeline> pipe;
  std::chrono::steady_clock::time_point stepStart;
  double lastStepHostAfterMs = 0, lastStepWallMs = 0;  // the rest is in the recorder's submission log
  // One recorder and one loss readback per step in flight (FieldPipeline::kStepsInFlight); a step
  // uses those of its slot. Declared after pipe: destroyed first, each waiting for its submission.
  static constexpr uint32_t kSlots = models::FieldPipeline::kStepsInFlight;
  std::array<std::unique_ptr<gpu::Recorder>, kSlots> recs;
  std::array<gpu::Buffer, kSlots> lossReadback;
  struct InFlight {
    uint32_t step;  // from 0
    bool readLoss;
  };
  std::optional<InFlight> inFlight;       // submitted, not yet collected
  std::optional<StepStats> unreported;    // collected by settle(), not yet returned
  uint32_t lastCollectedSlot = 0;
  std::unique_ptr<Model> model;
  uint32_t step = 0;
  std::optional<double> runProgress;  // setRunProgress
  std::string capacityNote;

  // Where the rate schedule stands for the next step, in steps (nerf::OptimizerStep).
  nerf::OptimizerStep nextStep() const {
    if (!runProgress) return nerf::OptimizerStep::at(step);
    const double fraction = std::clamp(*runProgress, 0.0, 1.0);
    return {step, uint32_t(std::lround(fraction * double(config.decaySteps)))};
  }

  void submit(bool readLoss) {
    const uint32_t slot = models::FieldPipeline::slotOf(step);
    recs[slot]->startLog();
    pipe->submitTrainStep(*recs[slot], {pixels->bindings(), &cameras, numCameras, transparentPixels}, nextStep(),
                          lossReadback[slot]);
    inFlight = InFlight{step, readLoss};
    ++step;
  }
  // Waits for a submitted step and reads what it left for the host.
  StepStats collect(const InFlight& f) {
    const uint32_t slot = models::FieldPipeline::slotOf(f.step);
    recs[slot]->wait();
    lastCollectedSlot = slot;
    const auto size = pipe->collectTrainStep(f.step);
    StepStats st;
    st.step = f.step + 1;
    st.rays = size.rays;
    st.samples = size.samples;
    if (f.readLoss) {
      const uint32_t R = size.rays;
      auto stats = nerf::PhotometricLoss::summarize(
          lossReadback[slot].download<float>(gpu::groupsFor(R, nerf::PhotometricLoss::kRaysPerPartial)), R);
      st.hasLoss = true;
      st.loss = stats.mse;
      st.psnr = stats.psnr;
      if (!std::isfinite(st.loss))
        throw Error("training diverged: loss is " + std::to_string(st.loss) + " at step " + std::to_string(st.step));
    }
    return st;
  }
  // Before the host reads or changes the model's state: the step in flight finished and collected
  // (its statistics kept for the next submitStep or finishSteps).
  void settle() {
    if (!inFlight) return;
    const InFlight f = *inFlight;
    inFlight.reset();
    unreported = collect(f);
  }
  std::optional<StepStats> takeReport() {
    std::optional<StepStats> r;
    std::swap(r, unreported);
    return r;
  }

  // The cameras the checkpoint records: with camera refinement the refined poses, what the model
  // was fitted through, not what the dataset said.
  std::vector<Camera> savedCameras() const {
    std::vector<Camera> out = trainCameras;
    const auto corrections = pipe->cameraCorrections();
    for (size_t i = 0; i < corrections.size() && i < out.size(); ++i) {
      const std::array<double, 6> c{corrections[i][0], corrections[i][1], corrections[i][2],
                                    corrections[i][3], corrections[i][4], corrections[i][5]};
      const auto pose = core::correctedPose<double>(out[i].c2w, c.data());
      for (int k = 0; k < 16; ++k) out[i].c2w[k] = float(pose[k]);
    }
    return out;
  }
  std::vector<TrainedCamera> namedSavedCameras() const {
    std::vector<Camera> cams = savedCameras();
    std::vector<TrainedCamera> out;
    for (size_t i = 0; i < cams.size(); ++i) out.push_back({names[i], cams[i]});
    return out;
  }
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
  s.box = train.bounds;
  s.numCameras = uint32_t(train.cameras.size());
  s.imageWidth = train.images[0].width;
  s.imageHeight = train.images[0].height;
  s.trainCameras = train.cameras;
  s.names = train.names;
  s.names.resize(train.cameras.size());  // a hand-made dataset may name no image
  std::vector<io::ImageSize> sizes;
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
  if (s.config.isFast()) s.capacityNote = models::chooseFastModel(s.config.fastModel(), train, ctx->isCpu(), s.transparentPixels);
  // The fit is checked before the pixels are allocated: the pixels alone first, then with the
  // model's buffers, which are measured by building the model (its size follows the configuration,
  // not the dataset).
  const uint64_t deviceBytes = nerf::deviceMemoryBytes(*ctx);
  const std::string device = "the device (" + ctx->deviceName() + ")";
  io::requireFit("training", sizes, 0, "", deviceBytes, device);
  auto layout = nerf::planPixelBindings(pixelCounts, nerf::pixelBytesPerBinding(*ctx));
  s.pipe = models::makeFieldPipeline(*ctx, s.config, s.box, s.config.raysPerBatch, true);
  io::requireFit("training", sizes, s.pipe->memory()->bytes(), "model", deviceBytes, device);
  // On a CPU device the device's memory is the host's: the pixels come out of what is left of it.
  if (ctx->isCpu()) io::requireFit("training", sizes, 0, "", io::availableHostBytes(), "host memory (available)");
  s.pixels = std::make_unique<nerf::TrainingPixels>(*ctx, layout);
  for (uint32_t i = 0; i < s.numCameras; ++i) {
    s.pixels->upload(i, train.images[i].rgba.data());
    if (release) std::vector<uint8_t>().swap(release->images[i].rgba);
  }
  s.cameras = gpu::Buffer::of(*ctx, nerf::packCameras(train.cameras, layout.images));
  s.pipe->markUnseenEmpty(train.cameras);
  s.pipe->setTrainingCameras(s.numCameras);
  for (uint32_t k = 0; k < Impl::kSlots; ++k) {
    s.recs[k] = std::make_unique<gpu::Recorder>(*ctx, true);
    s.lossReadback[k] = gpu::Buffer::hostReadable(*ctx, s.pipe->lossPartials().size(), "a training step's loss partials");
  }
  auto m = std::make_unique<Model::Impl>();
  m->ctx = ctx;
  m->config = s.config;
  m->box = s.box;
  m->pipe = s.pipe.get();
  m->trainingCameras = [&s] { return s.namedSavedCameras(); };  // s owns the model: it outlives it
  m->settle = [&s] { s.settle(); };
  s.model.reset(new Model(std::move(m)));
}

Trainer::~Trainer() = default;
uint32_t Trainer::steps() const { return impl_->step; }

void Trainer::setRunProgress(std::optional<double> fraction) {
  if (fraction && !std::isfinite(*fraction)) throw Error("Trainer::setRunProgress: the fraction is not finite");
  impl_->runProgress = fraction;
}

double Trainer::learningRate() const { return models::adamConfigOf(impl_->config).learningRate(impl_->nextStep().rateStep); }
std::vector<std::pair<std::string, double>> Trainer::lastStepTimings() const {
  impl_->settle();
  std::vector<std::pair<std::string, double>> all;
  for (const auto& sub : impl_->recs[impl_->lastCollectedSlot]->submissions())
    all.insert(all.end(), sub.kernels.begin(), sub.kernels.end());
  return all;
}

StepProfile Trainer::lastStepProfile() const {
  impl_->settle();
  StepProfile p;
  for (const auto& sub : impl_->recs[impl_->lastCollectedSlot]->submissions())
    p.submissions.push_back({sub.hostBeforeMs, sub.waitMs, sub.kernels});
  p.hostAfterMs = impl_->lastStepHostAfterMs;
  p.wallMs = impl_->lastStepWallMs;
  return p;
}
const Model& Trainer::model() const { return *impl_->model; }
std::vector<Camera> Trainer::cameras() const {
  impl_->settle();
  return impl_->savedCameras();
}

StepStats Trainer::step(bool readLoss) {
  auto& s = *impl_;
  s.settle();
  s.unreported.reset();  // step() reports its own step: what a submitStep left unreported is dropped
  s.stepStart = std::chrono::steady_clock::now();
  s.submit(readLoss);
  const auto st = s.collect(*s.inFlight);
  s.inFlight.reset();
  s.lastStepHostAfterMs = s.recs[s.lastCollectedSlot]->msSinceLastWait();
  s.lastStepWallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - s.stepStart).count();
  return st;
}

std::optional<StepStats> Trainer::submitStep(bool readLoss) {
  auto& s = *impl_;
  const auto start = std::chrono::steady_clock::now();
  const std::optional<Impl::InFlight> previous = s.inFlight;
  s.submit(readLoss);  // queued behind `previous`, which the device may still run
  if (previous) s.unreported = s.collect(*previous);
  s.lastStepHostAfterMs = s.recs[s.lastCollectedSlot]->msSinceLastWait();
  s.lastStepWallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return s.takeReport();
}

std::optional<StepStats> Trainer::finishSteps() {
  impl_->settle();
  return impl_->takeReport();
}

uint32_t Trainer::stepsInFlight() const { return impl_->inFlight ? 1 : 0; }

ModelStatistics Trainer::statistics() const {
  impl_->settle();
  return impl_->pipe->statistics();
}
double Trainer::trainingPixelsDeviceMiB() const { return double(impl_->pixels->bytes()) / double(1 << 20); }
uint32_t Trainer::trainingPixelBindings() const { return uint32_t(impl_->pixels->bindings().size()); }
const std::string& Trainer::capacityNote() const { return impl_->capacityNote; }

void Trainer::save(const std::string& path) const {
  auto& s = *impl_;
  s.settle();
  io::Checkpoint ck;
  ck.config = io::CheckpointRecord::write(s.config, s.step, s.box, {s.numCameras, s.imageWidth, s.imageHeight},
                                           s.namedSavedCameras());
  for (auto& a : s.pipe->state()) ck.put(a.name, a.buffer->download<float>(a.count));
  ck.save(path);
}

TrainConfig Trainer::configOf(const std::string& path) {
  return io::CheckpointRecord(io::Checkpoint::load(path)).config();
}

void Trainer::resume(const std::string& path) {
  auto& s = *impl_;
  s.settle();
  auto ck = io::Checkpoint::load(path);
  const io::CheckpointRecord record(ck);
  const TrainConfig saved = record.config();
  if (!record.sameModel(s.config))
    throw Error(path + ": checkpoint model config differs from this run's (" + saved.describe() + ")");
  io::SceneFacts scene;
  scene.box = s.box;
  scene.cameras = s.numCameras;
  scene.imageSize = {s.imageWidth, s.imageHeight};
  record.checkScene(scene);
  uploadState(ck, *s.pipe, s.box);
  s.step = record.step();
}

}  // namespace vknerf

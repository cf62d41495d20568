#pragma once
// Training and rendering a NeRF. Everything numerical runs on the context's device; the host only
// records command buffers and reads back what it reports.
//
//   auto ctx = vknerf::Context::create();
//   auto data = vknerf::Dataset::load("assets/tabletop");
//   vknerf::Trainer trainer(ctx, data, vknerf::TrainConfig::vanilla(*ctx));
//   for (int i = 0; i < 1000; ++i) trainer.step();
//   trainer.save("tabletop.vknerf");
//   auto view = vknerf::Model::load(ctx, "tabletop.vknerf").render(data.cameras[0]);
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vknerf/config.h"
#include "vknerf/dataset.h"
#include "vknerf/kernel_times.h"
#include "vknerf/model.h"
#include "vknerf/model_statistics.h"

namespace vknerf {

struct StepStats {
  uint32_t step = 0;
  bool hasLoss = false;  // loss is read back only when asked (every K steps)
  double loss = 0;       // fine-pass MSE of this step's batch (the photometric term)
  double psnr = 0;
  // With the loss: the other terms the step minimised, each named by the configuration field that
  // weighs it ("distortion_loss", "camera_penalty") with its weight applied, in the model's order.
  std::vector<std::pair<std::string, double>> lossTerms;
  uint32_t rays = 0;     // rays in this step's batch (the fast model adapts it)
  uint64_t samples = 0;  // field evaluations (points through the MLP) in this step
};

// Where one training step's wall time went (Trainer::lastStepProfile): each submission of work to
// the device with the host time before it and the time the host waited for it, and the device
// time of its kernels (GPU timestamps; the rest of a wait is dispatch overhead and untimed gaps).
// The host times of all submissions, their waits and hostAfterMs add up to wallMs.
struct StepProfile {
  struct Submission {
    double hostBeforeMs = 0;  // host work before it: recording, reading back counts
    double waitMs = 0;        // from submission until the host saw it finish
    KernelTimes kernels;  // milliseconds per kernel, in recording order
  };
  std::vector<Submission> submissions;
  double hostAfterMs = 0;  // after the last wait: reading the loss, bookkeeping
  double wallMs = 0;
};

class Trainer {
 public:
  Trainer(std::shared_ptr<Context> ctx, const Dataset& train, const TrainConfig& config);
  // The same, releasing each image's host pixels as soon as they are on the device, so that the
  // host never holds the whole set twice (on a CPU device the device's memory is the host's).
  Trainer(std::shared_ptr<Context> ctx, Dataset&& train, const TrainConfig& config);
  ~Trainer();

  // One optimisation step over a random batch of rays (recorded into one command buffer), waited
  // for: its own statistics. A step still in flight from submitStep finishes first (and its
  // statistics are dropped).
  StepStats step(bool readLoss = false);
  // One step queued behind the one still running, not waited for: the host records this step
  // while the device runs the previous one, so neither waits for the other. Returns the statistics
  // of the step before it, now finished (none on the first call). A run's numbers are bit for bit
  // those of step(): what the host decides from a step (the fast model's ray count) applies two
  // steps later either way. Reading the model or the trainer's state (save, statistics, cameras,
  // the model's render or mesh) waits for the step in flight first.
  std::optional<StepStats> submitStep(bool readLoss = false);
  // Waits for the step in flight; its statistics, unless already returned (none when none ran).
  std::optional<StepStats> finishSteps();
  // Steps submitted and not yet waited for: 0 or 1.
  uint32_t stepsInFlight() const;
  uint32_t steps() const;
  // Fits the learning rates' decay to a run of known length: `fraction` is how much of the run is
  // done (0 at its start, 1 at its end: by steps, or by time for a time budget), and the rates
  // decay from lr to lr_final over the run, whatever its number of steps. Call it before each step.
  // Without it (or after std::nullopt) the decay follows the step count over decay_steps. Either
  // way the rates hold at lr_final once the decay is done.
  void setRunProgress(std::optional<double> fraction);
  // The field's learning rate the next step takes (the hash table's is a multiple of it).
  double learningRate() const;
  const Model& model() const;
  // The training cameras as the model is fitted through them: the dataset's, with their learned
  // corrections applied when the fast model refines cameras (FastModel::refineCameras).
  std::vector<Camera> cameras() const;
  // Device milliseconds per kernel of the last step (GPU timestamps), in recording order.
  std::vector<std::pair<std::string, double>> lastStepTimings() const;
  // The whole last step: its submissions, the host time between them, and its wall time.
  StepProfile lastStepProfile() const;
  // What the model spends: parameters, device memory, samples per ray, occupancy (fast model).
  ModelStatistics statistics() const;
  // Device memory the training images take (RGBA8), and the storage buffers they are spread over.
  double trainingPixelsDeviceMiB() const;
  uint32_t trainingPixelBindings() const;
  // How the fast model's capacity left open in the configuration (hash table size, finest
  // resolution: 0) was chosen from the training data, one line; "" when nothing was left open.
  const std::string& capacityNote() const;

  // Checkpoint: config, parameters, Adam state, the step and the training cameras (Model::trainingCameras),
  // written atomically.
  void save(const std::string& path) const;
  // Continue exactly from a checkpoint written by save() for the same dataset; throws vknerf::Error when
  // its model config, scene box, camera count or image size differ from this trainer's.
  void resume(const std::string& path);
  // The training configuration stored in a checkpoint (to resume with exactly the same settings).
  static TrainConfig configOf(const std::string& path);

 private:
  Trainer(std::shared_ptr<Context> ctx, const Dataset& train, const TrainConfig& config, Dataset* release);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vknerf

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
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vknerf/camera.h"
#include "vknerf/config.h"
#include "vknerf/context.h"
#include "vknerf/dataset.h"
#include "vknerf/mesh.h"
#include "vknerf/render_target.h"

namespace vknerf {

struct RenderedImage {
  uint32_t width = 0, height = 0;
  std::vector<float> rgb;      // 3 per pixel, composited over the background
  std::vector<float> depth;    // expected depth sum w_i t_i / opacity (0 where opacity is ~0)
  std::vector<float> opacity;  // 1 - T_final
  // 3 per pixel: the colour behind the field that rgb is composited over (a learned far field's
  // colour in the pixel's direction, else the constant background); empty in images made by hand.
  std::vector<float> background;
};

struct StepStats {
  uint32_t step = 0;
  bool hasLoss = false;  // loss is read back only when asked (every K steps)
  double loss = 0;       // fine-pass MSE of this step's batch
  double psnr = 0;
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
    std::vector<std::pair<std::string, double>> kernels;  // milliseconds per kernel, in recording order
  };
  std::vector<Submission> submissions;
  double hostAfterMs = 0;  // after the last wait: reading the loss, bookkeeping
  double wallMs = 0;
};

// What a model spends and how its samples fall (Trainer::statistics).
struct ModelStatistics {
  uint64_t mlpParameters = 0;       // every network's weights and biases
  uint64_t encodingParameters = 0;  // trainable encoding entries: the hash grid's (fast model), else 0
  double deviceMiB = 0;             // every device buffer the model's pipeline has allocated
  double samplesPerRay = 0;         // MLP queries per ray: coarse + fine (vanilla), marched in the last step (fast)
  uint32_t raysPerStep = 0;         // in the last step (the fast model adapts it)
  uint64_t samplesPerStep = 0;      // field evaluations in the last step
  // Fast model only.
  std::optional<double> occupiedFraction;     // occupancy-grid cells marked occupied
  std::vector<double> occupiedFractionPerCascade;  // the same per cascade, innermost first
  std::optional<double> occupiedBoxFraction;  // the occupied cells' bounding box over the scene box (volume)
  std::optional<double> meanSamplesPerRay;       // marched per ray, over all steps
  std::optional<double> keptByEarlyTermination;  // samples kept by early termination, over all steps
};

// The field at a batch of points (Model::queryField).
struct FieldSamples {
  std::vector<float> density;  // sigma per point, after the model's density activation
  std::vector<float> rgb;      // 3 per point: the colour seen along the point's direction
};

// Sampling when rendering a loaded model; 0 keeps what the model was trained with.
struct RenderSettings {
  uint32_t coarseSamples = 0, fineSamples = 0;  // vanilla: stratified + importance samples per ray
  uint32_t marchSteps = 0;                      // fast: march steps per scene-box diagonal
  // fast: a ray stops once its transmittance is below this (what lies behind adds less than that
  // times its colour); 0 shades every sample the march finds. In [0, 1).
  float minTransmittance = 1e-4f;
};

// A trained field: the model configuration, its parameters and the scene box.
class Model {
 public:
  static Model load(std::shared_ptr<Context> ctx, const std::string& checkpoint, const RenderSettings& settings = {});
  ~Model();
  Model(Model&&) noexcept;
  Model& operator=(Model&&) noexcept;

  const TrainConfig& config() const;
  const Aabb& bounds() const;
  // Renders on the device, waits, and reads the image back.
  // `progress`, when given, is called after each tile of rays with (pixels done, pixels in all).
  RenderedImage render(const Camera& camera,
                       const std::function<void(uint64_t done, uint64_t total)>& progress = {}) const;
  // Records the render of `camera` into the caller's command buffer `cmd` (primary, recording, from
  // a pool of the context's queue family), writing `target`; nothing is submitted. Contract (see
  // docs/embedding.md): before the commands, the caller makes earlier writes to the target visible
  // to VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT / VK_ACCESS_SHADER_WRITE_BIT (and transitions an image
  // to GENERAL); after them, it barriers from COMPUTE_SHADER / SHADER_WRITE to its own use. The
  // model's scratch buffers are reused by every recording: one render of a model may be in flight
  // at a time, and the model must outlive the commands' execution.
  void recordRender(VkCommandBuffer cmd, const Camera& camera, const RenderTarget& target) const;

  // The field at `points` (xyz each, world coordinates) seen along `directions` (xyz each, one per
  // point, normalised here), evaluated on the device in batches. Not while a render is in flight.
  FieldSamples queryField(const std::vector<float>& points, const std::vector<float>& directions) const;
  // The surface where the density crosses settings.threshold: the density sampled on a grid over
  // the box on the device, marching cubes there, each vertex coloured by the field seen from
  // outside (along the negative vertex normal). Throws vknerf::Error for an empty box or a
  // resolution below 2 or beyond what the device's buffers hold. `progress`, when given, is called
  // after each batch of density samples, the long part, with (samples queried, samples to query).
  Mesh extractMesh(const MeshSettings& settings = {},
                   const std::function<void(uint64_t done, uint64_t total)>& progress = {}) const;

 private:
  friend class Trainer;
  struct Impl;
  explicit Model(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

class Trainer {
 public:
  Trainer(std::shared_ptr<Context> ctx, const Dataset& train, const TrainConfig& config);
  // The same, releasing each image's host pixels as soon as they are on the device, so that the
  // host never holds the whole set twice (on a CPU device the device's memory is the host's).
  Trainer(std::shared_ptr<Context> ctx, Dataset&& train, const TrainConfig& config);
  ~Trainer();

  // One optimisation step over a random batch of rays (recorded into one command buffer).
  StepStats step(bool readLoss = false);
  uint32_t steps() const;
  const Model& model() const;
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

  // Checkpoint: config, parameters, Adam state and the step, written atomically.
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

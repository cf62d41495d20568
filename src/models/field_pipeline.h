#pragma once
// What Model and Trainer drive: one model configuration's whole device pipeline (vanilla:
// nerf::VanillaPipeline, fast: nerf::FastPipeline), rendering a block of pixels and, when built for
// training, one optimisation step. Buffers are allocated once for a ray capacity; every buffer a
// pipeline allocates, when it is built or later, is charged to its memory account.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/memory/memory_account.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/occupancy/occupancy_grid.h"
#include "nerf/optim/adam.h"
#include "vknerf/camera.h"
#include "vknerf/config.h"
#include "vknerf/model_statistics.h"
#include "vknerf/render_settings.h"

namespace vknerf::models {

struct FieldBatch;

// Rays start this far in front of the camera (or at the scene box, whichever is further), in the
// scene's units: the vanilla model's, and the fast model's where its configuration leaves it at 0
// (models saved before FastModel::nearDistance).
constexpr float kNearPlane = 0.05f;

// A named float array of the model's state, for checkpoints.
struct StateArray {
  std::string name;
  gpu::Buffer* buffer;
  size_t count;
  bool optimizer;  // Adam moments: saved for resuming, not needed to render
  bool numbers = true;  // floats, checked finite on load; false for words of bits stored in float slots
};

// The training set on the device: the pixel bindings (nerf::TrainingPixels) and the cameras packed
// with each image's place in them (nerf::packCameras).
struct TrainingData {
  std::span<const gpu::BufferRange> pixels;
  const gpu::Buffer* cameras;
  uint32_t numCameras;
  // Some pixel has alpha < 255. Only then does a random background teach something (that the
  // transparent space is empty); behind opaque photos it is noise, and the constant one is used.
  bool transparentPixels = true;
};

// A block of one view to render, as one value: pixels [first, first + count) (row-major) of camera
// `camera` in `cameras` (nerf::packCameras), over a constant `background`.
struct ViewBlock {
  gpu::BufferRange cameras;
  uint32_t camera = 0, first = 0, count = 0;
  std::array<float, 3> background{};
};

class FieldPipeline {
 public:
  virtual ~FieldPipeline() = default;

  virtual uint32_t rayCapacity() const = 0;

  // Renders `view` (a block of view.count <= rayCapacity() pixels). Afterwards color() holds vec4
  // (rgb over view.background, opacity) and depth()
  // the float sum w_i t_i, per ray. mayWait: `rec` is the pipeline's own and it may end, submit and
  // re-begin it to size later work from counts on the device; false: everything is recorded into
  // `rec` (a caller's command buffer) and nothing is submitted.
  void recordRender(gpu::Recorder& rec, const ViewBlock& view, bool mayWait) {
    gpu::MemoryAccount::Scope charge(memory_);
    doRecordRender(rec, view, mayWait);
  }
  virtual const gpu::Buffer& color() const = 0;
  virtual const gpu::Buffer& depth() const = 0;
  // vec4 (r, g, b, -) per ray of the last recorded render: what color() is composited over.
  virtual const gpu::Buffer& backgrounds() const = 0;

  // The field at points chosen by the caller (an exporter): queryBatch()'s positions (vec4, the
  // scene box mapped onto [-1, 1]^3) and directions (vec4, unit) for `count` <= its capacity points
  // give its field (vec4 rgb, sigma) as a render evaluates it. The batch is the render's own: not
  // while a render is in flight.
  virtual FieldBatch& queryBatch() = 0;
  virtual void recordQuery(gpu::Recorder& rec, uint32_t count) = 0;
  // Where a render marches at all: the occupancy grid's bits (fast model), for an exporter that
  // samples the field only there; none for a model that marches everywhere (vanilla).
  virtual std::optional<nerf::OccupancyBits> occupancyBits() const { return std::nullopt; }

  // Training runs kStepsInFlight steps deep: step N is recorded and submitted while step N-1 still
  // runs on the device, and the host reads what step N-1 left (its counts, its loss) only after
  // that. Whatever the host decides from a step's counts (the fast model's ray count) applies to the
  // step kStepsInFlight later, however the caller waits, so a run's numbers do not depend on when
  // the host looked. A step's host-side slot is at.step % kStepsInFlight.
  static constexpr uint32_t kStepsInFlight = 2;
  static uint32_t slotOf(uint32_t step) { return step % kStepsInFlight; }
  struct StepSize {
    uint32_t rays = 0;
    uint64_t samples = 0;
  };
  // One optimisation step (`at.step` counts from 0), recorded into `rec` (begun here) and
  // submitted, not waited for. Within the step, the loss partials are copied into `lossReadback`
  // (host-readable, lossPartials()'s size); returns the rays whose partials it recorded.
  uint32_t submitTrainStep(gpu::Recorder& rec, const TrainingData& data, nerf::OptimizerStep at, gpu::Buffer& lossReadback) {
    gpu::MemoryAccount::Scope charge(memory_);
    rec.begin();
    const uint32_t recorded = doRecordTrainStep(rec, data, at);
    rec.copy(lossPartials(), lossReadback, lossPartials().size());
    rec.end();
    rec.submit();
    return recorded;
  }
  // After the step's submission finished (its recorder waited for): the rays whose loss its
  // partials hold (the rays past the device's cut add zero) and the field evaluations it made.
  StepSize collectTrainStep(uint32_t step) { return doCollectTrainStep(slotOf(step)); }
  virtual const gpu::Buffer& lossPartials() const = 0;
  // Before the first step: the training cameras, so that space none of them sees is never modelled
  // (the fast model's occupancy grid marks it empty for good). A model without such a structure ignores them.
  virtual void markUnseenEmpty(std::span<const Camera> cameras) { (void)cameras; }
  // Before the first step and before a resume loads the state: how many training cameras there
  // are, for state kept per camera (the fast model's camera refinement).
  virtual void setTrainingCameras(uint32_t count) { (void)count; }
  // Each training camera's learned pose correction (w, tau: nerf/rays/pose_correction.h), read
  // back; empty when the cameras are not refined.
  virtual std::vector<std::array<float, 6>> cameraCorrections() { return {}; }

  // Parameters (and, when training, optimizer state and auxiliary structures) by name.
  virtual std::vector<StateArray> state() = 0;
  // What the model spends; deviceMiB counts every buffer charged to the pipeline.
  ModelStatistics statistics() {
    ModelStatistics s = modelStatistics();
    s.deviceMiB = double(memory_->bytes()) / double(1 << 20);
    return s;
  }

  // The account the pipeline's buffers are charged to: open it (MemoryAccount::Scope) while
  // constructing a pipeline, as makeFieldPipeline does.
  const std::shared_ptr<gpu::MemoryAccount>& memory() const { return memory_; }

 protected:
  // The account open on this thread when the pipeline is constructed, or a new one.
  FieldPipeline() : memory_(gpu::MemoryAccount::current() ? gpu::MemoryAccount::current()
                                                           : std::make_shared<gpu::MemoryAccount>()) {}

 private:
  virtual void doRecordRender(gpu::Recorder& rec, const ViewBlock& view, bool mayWait) = 0;
  // Records the step's commands into the begun `rec`; returns the rays it recorded.
  virtual uint32_t doRecordTrainStep(gpu::Recorder& rec, const TrainingData& data, nerf::OptimizerStep at) = 0;
  virtual StepSize doCollectTrainStep(uint32_t slot) = 0;
  virtual ModelStatistics modelStatistics() = 0;

  std::shared_ptr<gpu::MemoryAccount> memory_;
};

// Rays per render batch of a loaded model.
constexpr uint32_t kRenderRays = 4096;

// The pipeline for config.model, its buffers charged to its own memory account; `overrides` are a
// loaded model's render-time sampling settings (zero fields keep the trained ones).
std::unique_ptr<FieldPipeline> makeFieldPipeline(Context& ctx, const TrainConfig& config, const Aabb& box,
                                                 uint32_t rayCapacity, bool training,
                                                 const RenderSettings& overrides = {});

}  // namespace vknerf::models

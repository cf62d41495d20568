#pragma once
// What Model and Trainer drive: one model configuration's whole device pipeline (vanilla:
// models::VanillaPipeline, fast: models::FastPipeline), rendering a block of pixels and, when built
// for training, one optimisation step. Buffers are allocated once for a ray capacity; every buffer a
// pipeline allocates, when it is built or later, is charged to its memory account. A pipeline's
// state is one registry of parts (models/common/parameter_groups.h): its optimizer steps, its
// checkpoint and its parameter counts; per-photo state trained beside the field is a step extension
// (models/common/step_extension.h), which the pipeline calls at fixed points of its step.
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
#include "models/common/loss_report.h"
#include "models/common/parameter_groups.h"
#include "models/common/step_extension.h"
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

  uint32_t rayCapacity() const { return rayCapacity_; }

  // Renders `view` (a block of view.count <= rayCapacity() pixels). Afterwards color() holds vec4
  // (rgb over view.background, opacity) and depth()
  // the float sum w_i t_i, per ray. mayWait: `rec` is the pipeline's own and it may end, submit and
  // re-begin it to size later work from counts on the device; false: everything is recorded into
  // `rec` (a caller's command buffer) and nothing is submitted.
  void recordRender(gpu::Recorder& rec, const ViewBlock& view, bool mayWait) {
    gpu::MemoryAccount::Scope charge(memory_);
    doRecordRender(rec, view, mayWait);
  }
  // What the last recorded render wrote, per ray: colour (vec4: rgb over its background, opacity),
  // depth (float) and the background each colour is composited over (vec4 r, g, b, -).
  struct RenderOutputs {
    const gpu::Buffer &color, &depth, &background;
  };
  virtual RenderOutputs renderOutputs() const = 0;
  const gpu::Buffer& color() const { return renderOutputs().color; }
  const gpu::Buffer& depth() const { return renderOutputs().depth; }
  const gpu::Buffer& backgrounds() const { return renderOutputs().background; }
  // Field samples the renders recorded with mayWait have shaded since the pipeline was built (the
  // fast model's: in front of where each ray became opaque, up to a segment's end).
  uint64_t renderedSamples() const { return renderedSamples_; }

  // The field at points chosen by the caller (an exporter): queryBatch()'s positions (vec4, the
  // scene box mapped onto [-1, 1]^3) and directions (vec4, unit) for `count` <= its capacity points
  // give its field (vec4 rgb, sigma) as a render evaluates it. The batch is the render's own: not
  // while a render is in flight.
  virtual FieldBatch& queryBatch() = 0;
  virtual void recordQuery(gpu::Recorder& rec, uint32_t count) = 0;
  // Where a render samples the field at all (the fast model's occupied cells), for an exporter that
  // samples it only there; none for a model that samples everywhere (vanilla).
  virtual std::optional<nerf::OccupancyBits> sampledCells() const { return std::nullopt; }

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
  // submitted, not waited for. Within the step, the loss partials (every term's) are copied into
  // `lossReadback` (host-readable, lossPartials()'s size); returns the rays whose partials it
  // recorded (lossReport().summarize reads them).
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
  // A training pipeline's loss terms and their partials (models/common/loss_report.h).
  const LossReport& lossReport() const { return lossReport_.value(); }
  const gpu::Buffer& lossPartials() const { return lossReport().partials(); }

  // Parameters (and, when training, optimizer state and auxiliary structures) by name.
  std::vector<StateArray> state() { return parts_.state(); }
  // The training cameras (as given, one per photo) as the model was fitted through them: with
  // camera refinement, the refined poses.
  std::vector<Camera> trainedCameras(std::span<const Camera> given);
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
  // The account open on this thread when the pipeline is constructed, or a new one. A training
  // pipeline reports its loss through a LossReport for its ray capacity.
  FieldPipeline(Context& ctx, uint32_t rayCapacity, bool training)
      : rayCapacity_(rayCapacity),
        memory_(gpu::MemoryAccount::current() ? gpu::MemoryAccount::current() : std::make_shared<gpu::MemoryAccount>()) {
    if (training) lossReport_.emplace(ctx, rayCapacity);
  }
  LossReport& report() { return lossReport_.value(); }
  void countRenderedSamples(uint64_t samples) { renderedSamples_ += samples; }

  // The model's parts, registered once in checkpoint order by the model's constructor.
  ParameterGroups& parts() { return parts_; }
  const ParameterGroups& parts() const { return parts_; }
  void addExtension(StepExtension& extension) {
    parts_.add(extension);
    extensions_.push_back(&extension);
  }
  std::span<StepExtension* const> extensions() const { return extensions_; }

 private:
  virtual void doRecordRender(gpu::Recorder& rec, const ViewBlock& view, bool mayWait) = 0;
  // Records the step's commands into the begun `rec`; returns the rays it recorded.
  virtual uint32_t doRecordTrainStep(gpu::Recorder& rec, const TrainingData& data, nerf::OptimizerStep at) = 0;
  virtual StepSize doCollectTrainStep(uint32_t slot) = 0;
  virtual ModelStatistics modelStatistics() = 0;

  uint32_t rayCapacity_;
  std::shared_ptr<gpu::MemoryAccount> memory_;
  ParameterGroups parts_;
  std::vector<StepExtension*> extensions_;
  std::optional<LossReport> lossReport_;
  uint64_t renderedSamples_ = 0;
};

// Rays per render batch of a loaded model (RenderSettings::raysPerBatch 0). A batch is one
// submission: the fast model's 16384 (about 11 KB of device memory a ray) spend 8% of a view's wall
// outside the kernels on lavapipe where 4096 spent 10 to 12%, and its per-ray kernels get 4 times
// the workgroups (docs/real_captures.md, "Render batches"). The vanilla model's samples carry
// wide activations, so it keeps 4096.
uint32_t renderRaysOf(const TrainConfig& config);

// The pipeline for config.model, its buffers charged to its own memory account; `overrides` are a
// loaded model's render-time sampling settings (zero fields keep the trained ones); `photos`: the
// training photos, for state kept per photo and, when their cameras are given, the space none of
// them sees (never modelled).
std::unique_ptr<FieldPipeline> makeFieldPipeline(Context& ctx, const TrainConfig& config, const Aabb& box,
                                                 uint32_t rayCapacity, bool training,
                                                 const RenderSettings& overrides = {}, const TrainingPhotos& photos = {});

}  // namespace vknerf::models

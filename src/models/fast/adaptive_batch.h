#pragma once
// The fast model's training batch size, decided on the host from what the device counted: a step
// marches an unknown number of samples per ray, so each step's counts (its whole rays, the samples
// it marched and those in front of each ray's cut) are copied within its own submission into
// host-readable memory, one buffer per step in flight, and read after its wait; they set the ray
// count of the step kStepsInFlight later (about FastModel::samplesPerBatch samples), tell the
// forward whether segments pay (the kept fraction) and feed the model's statistics.
#include <array>
#include <cstdint>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/field_pipeline.h"
#include "vknerf/model_statistics.h"

namespace vknerf::models {

class AdaptiveBatch {
 public:
  static constexpr uint32_t kSlots = FieldPipeline::kStepsInFlight;

  // Ray counts in [rayAlign, rayCapacity], aiming at samplesPerBatch marched samples; the first
  // steps take min(rayCapacity, 1024) rays.
  AdaptiveBatch(Context& ctx, uint32_t rayCapacity, uint32_t rayAlign, uint32_t samplesPerBatch);

  // The rays the next step in `slot` trains on.
  uint32_t rays(uint32_t slot) const { return raysFor_[slot]; }
  // Within the step in `slot`: its counts copied for the host, each the first uint of its buffer
  // (kept: the samples in front of the rays' cuts; none without early termination, when every
  // marched sample counts).
  struct DeviceCounts {
    const gpu::Buffer& wholeRays;
    const gpu::Buffer& marched;
    const gpu::Buffer* kept;
  };
  void recordCopy(gpu::Recorder& rec, uint32_t slot, const DeviceCounts& counts);
  // After the step's wait: its rays and the samples it trained on; sets the ray count of the next
  // step in the slot.
  FieldPipeline::StepSize collect(uint32_t slot);

  // Of the last collected step's marched samples, those in front of the cut (1 before any).
  double lastKeptFraction() const { return lastKeptFraction_; }
  void addStatistics(ModelStatistics& s) const;

 private:
  uint32_t rayCapacity_, rayAlign_, samplesPerBatch_;
  std::array<gpu::Buffer, kSlots> counts_;  // host-readable: rays, marched and kept samples
  std::array<bool, kSlots> kept_{};          // the slot's step copied a kept count
  std::array<uint32_t, kSlots> raysFor_;
  double lastSamplesPerRay_ = 0, lastKeptFraction_ = 1;
  uint32_t lastRays_ = 0, lastSamples_ = 0;
  uint64_t marchedSamples_ = 0, keptSamples_ = 0, marchedRays_ = 0;
};

}  // namespace vknerf::models

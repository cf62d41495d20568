#pragma once
// Camera refinement: a learned pose correction per training photo (nerf/rays/pose_correction.h),
// trained with its own Adam state and rate and an L2 penalty that keeps each pose near the one the
// photo came with. A step extension (models/common/step_extension.h): each step applies the
// corrections to the training cameras before its rays are made (recordCameras), asks the field's
// backward for the position gradient of every sample, and sums it per camera on the device
// (recordGradient); the checkpoint records the corrected poses (adjustTrainedCameras).
#include <array>
#include <cstdint>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/common/loss_report.h"
#include "models/common/step_extension.h"
#include "models/common/trainable_parameters.h"
#include "nerf/rays/pose_correction.h"

namespace vknerf::models {

struct CameraRefinementSettings {
  nerf::AdamConfig adam;     // the corrections' own rate and schedule
  float penalty = 0;   // L2 weight on the corrections
};

class CameraRefinement final : public StepExtension {
 public:
  // rows: the most rows a training step's backward runs over (the position gradient's). With a
  // penalty, its value is a term of `report` (camera_penalty).
  CameraRefinement(Context& ctx, uint32_t numCameras, uint32_t rows, const CameraRefinementSettings& settings,
                   LossReport& report);

  uint32_t numCameras() const { return numCameras_; }
  // The training cameras (numCameras() CameraGpu) with the corrections applied, into a buffer of its own.
  const gpu::Buffer& recordCameras(gpu::Recorder& rec, const TrainingData& data) override;
  void requestGradients(FieldGradientTargets& targets) override { positionGradient_ = sharedTarget(targets.dPosition, dPosition_); }
  // The corrections' gradient from a trained batch (before the field's optimizer step). The
  // learned far field's colour also depends on the direction; that part is left out (its gradient
  // is small and blurred: a colour per direction at infinity).
  void recordGradient(gpu::Recorder& rec, const StepBatch& batch) override;
  void recordOptimizerStep(gpu::Recorder& rec, nerf::OptimizerStep at) override { corrections_.recordOptimizerStep(rec, at); }
  size_t parameterCount() const override { return corrections_.count(); }
  // "cameras.params" (6 per camera: w, tau) and Adam's moments, for checkpoints.
  void appendState(std::vector<StateArray>& out) override { corrections_.appendState(out); }
  // Each camera's pose composed with its correction (core pose algebra, as the kernel applies it).
  void adjustTrainedCameras(std::vector<Camera>& cameras) override;
  // The corrections now, read back.
  std::vector<std::array<float, nerf::kCorrectionFloats>> corrections();

 private:
  uint32_t numCameras_;
  float penalty_;
  TrainableParameters corrections_;
  gpu::Buffer corrected_;
  gpu::Buffer dPosition_;  // dL/dp per backward row (vec4)
  gpu::BufferRange positionGradient_;  // what the backward writes dL/dp into: dPosition_, or another asker's
  LossReport& report_;
  std::optional<uint32_t> penaltyTerm_;
  gpu::Buffer penaltyValues_;  // with a penalty: each camera's, for the report
  nerf::PoseCorrection kernels_;
};

}  // namespace vknerf::models

#pragma once
// Camera refinement: a learned pose correction per training photo (nerf/rays/pose_correction.h),
// trained with its own Adam state and rate and an L2 penalty that keeps each pose near the one the
// photo came with. Each step applies the corrections to the training cameras before its rays are
// made, and, after the field's backward, sums the gradient of the loss per camera on the device.
#include <array>
#include <cstdint>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/common/trainable_parameters.h"
#include "nerf/rays/pose_correction.h"

namespace vknerf::models {

struct CameraRefinementSettings {
  nerf::AdamConfig adam;     // the corrections' own rate and schedule
  float penalty = 0;   // L2 weight on the corrections
};

class CameraRefinement {
 public:
  CameraRefinement(Context& ctx, uint32_t numCameras, const CameraRefinementSettings& settings);

  uint32_t numCameras() const { return numCameras_; }
  // The training cameras (numCameras() CameraGpu) with the corrections applied, into cameras().
  void recordApply(gpu::Recorder& rec, const gpu::Buffer& trainingCameras);
  const gpu::Buffer& cameras() const { return corrected_; }
  // The corrections' gradient from a trained batch (before the field's optimizer step).
  void recordGradient(gpu::Recorder& rec, const nerf::PoseGradientInputs& in);
  void recordOptimizerStep(gpu::Recorder& rec, nerf::OptimizerStep at) { corrections_.recordOptimizerStep(rec, at); }
  // "cameras.params" (6 per camera: w, tau) and Adam's moments, for checkpoints.
  void appendState(std::vector<StateArray>& out) { corrections_.appendState(out); }
  // The corrections now, read back.
  std::vector<std::array<float, nerf::kCorrectionFloats>> corrections();

 private:
  uint32_t numCameras_;
  float penalty_;
  TrainableParameters corrections_;
  gpu::Buffer corrected_;
  nerf::PoseCorrection kernels_;
};

}  // namespace vknerf::models

#pragma once
// Camera refinement's kernels (stage 1, rays): the training cameras with their learned pose
// corrections applied before rays are made (shaders/rays/camera_correct.comp), and the gradient of
// the loss with respect to those corrections from the samples' position gradients
// (shaders/rays/camera_gradient.comp). A correction is 6 floats per camera, (w, tau): the pose
// [R | c] becomes [exp(w) R | c + tau] (src/core/camera/pose_algebra.h).
#include <cstdint>
#include <optional>

#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/rays/rays.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

constexpr uint32_t kCorrectionFloats = 6;

// What the gradient reads of a trained batch, as one value: its rays, in runs of one camera each
// (RayGeneration::RandomPixels::inCameraRuns, over the numCameras the gradient is for), and their
// camera ids, the march's packed offsets and samples (t), and dL/dp per row of the backward pass
// (vec4, p the position in the scene box mapped onto [-1, 1]^3), ray r's rows being
// [rowOffsets[r], rowOffsets[r + 1]), its first samples in order (all of them, or those kept
// before early termination). rayCount: a uint on the device, the rays of the batch that trained.
struct PoseGradientInputs {
  RaySpan rays;
  gpu::BufferRange pixelIds, marchedOffsets, rowOffsets, samples, positionGradient, rayCount;
  Aabb box;  // the box mapped onto [-1, 1]^3
};

class PoseCorrection {
 public:
  explicit PoseCorrection(Context& ctx);
  // corrected = cameras (count CameraGpu) with corrections (6 floats each) applied.
  void recordApply(gpu::Recorder& rec, uint32_t count, const gpu::BufferRange& cameras,
                   const gpu::BufferRange& corrections, const gpu::BufferRange& corrected);
  // grads (6 floats per camera, written) = dL/dcorrection + penalty * correction, for numCameras;
  // with penaltyValues (a float per camera), each camera's penalty / 2 |correction|^2 too.
  void recordGradient(gpu::Recorder& rec, const PoseGradientInputs& in, uint32_t numCameras, float penalty,
                      const gpu::BufferRange& corrections, const gpu::BufferRange& grads,
                      const std::optional<gpu::BufferRange>& penaltyValues = std::nullopt);

 private:
  gpu::Kernel apply_, gradient_;
  uint32_t maxGroups_;  // of the per-camera sums' dispatch
};

}  // namespace vknerf::nerf

#include "nerf/rays/pose_correction.h"

#include <algorithm>
#include <string>

#include "nerf/sampling/sample_layout.h"
#include "rays/camera_correct_shared.h"
#include "rays/camera_gradient_shared.h"
#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {
constexpr uint32_t kLocal = 64;
}  // namespace

PoseCorrection::PoseCorrection(Context& ctx)
    : apply_(ctx, {gpu::shaders::camera_correct, std::vector<gpu::Binding>(3, gpu::Binding::Storage),
                   sizeof(glsl::CameraCorrectPush), {}}),
      gradient_(ctx, {gpu::shaders::camera_gradient, std::vector<gpu::Binding>(10, gpu::Binding::Storage),
                      sizeof(glsl::CameraGradientPush), {}}),
      maxGroups_(ctx.properties().limits.maxComputeWorkGroupCount[0]) {}

void PoseCorrection::recordApply(gpu::Recorder& rec, uint32_t count, const gpu::BufferRange& cameras,
                                 const gpu::BufferRange& corrections, const gpu::BufferRange& corrected) {
  gpu::requireBytes("PoseCorrection", "cameras", cameras, uint64_t(count) * sizeof(CameraGpu));
  gpu::requireBytes("PoseCorrection", "corrected cameras", corrected, uint64_t(count) * sizeof(CameraGpu));
  gpu::requireBytes("PoseCorrection", "corrections", corrections, uint64_t(count) * kCorrectionFloats * 4);
  if (count == 0) return;
  rec.dispatch(apply_, {cameras, corrections, corrected}, glsl::CameraCorrectPush{count}, gpu::groupsFor(count, kLocal),
               1, 1, "camera_correct");
}

void PoseCorrection::recordGradient(gpu::Recorder& rec, const PoseGradientInputs& in, uint32_t numCameras,
                                    float penalty, const gpu::BufferRange& corrections, const gpu::BufferRange& grads,
                                    const std::optional<gpu::BufferRange>& penaltyValues) {
  const uint32_t R = in.rays.count;
  gpu::requireBytes("PoseCorrection", "rays", in.rays.range, uint64_t(R) * kRayBytes);
  gpu::requireBytes("PoseCorrection", "pixel ids", in.pixelIds, uint64_t(R) * kPixelIdBytes);
  gpu::requireBytes("PoseCorrection", "marched offsets", in.marchedOffsets, (uint64_t(R) + 1) * 4);
  gpu::requireBytes("PoseCorrection", "row offsets", in.rowOffsets, (uint64_t(R) + 1) * 4);
  gpu::requireBytes("PoseCorrection", "ray count", in.rayCount, 4);
  gpu::requireBytes("PoseCorrection", "corrections", corrections, uint64_t(numCameras) * kCorrectionFloats * 4);
  gpu::requireBytes("PoseCorrection", "gradients", grads, uint64_t(numCameras) * kCorrectionFloats * 4);
  if (penaltyValues) gpu::requireBytes("PoseCorrection", "penalty values", *penaltyValues, uint64_t(numCameras) * 4);
  if (numCameras == 0) return;
  glsl::CameraGradientPush p{};
  for (int k = 0; k < 3; ++k) p.positionScale[k] = 2.0f / (in.box.max[k] - in.box.min[k]);
  p.numCameras = numCameras;
  p.maxRays = R;
  p.penalty = penalty;
  p.writePenaltyValues = penaltyValues ? 1u : 0u;
  // gpu/per_camera_sum.glsl: a workgroup a camera at a time, as many as one dispatch holds.
  rec.dispatch(gradient_,
               {in.pixelIds, in.rays.range, in.marchedOffsets, in.rowOffsets, in.samples, in.positionGradient, corrections,
                grads, in.rayCount, penaltyValues ? *penaltyValues : grads},  // unwritten: a placeholder
               p, std::min(numCameras, maxGroups_), 1, 1, "camera_gradient");
}

}  // namespace vknerf::nerf

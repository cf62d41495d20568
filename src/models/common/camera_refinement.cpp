#include "models/common/camera_refinement.h"

#include <string>

#include "core/camera/pose_algebra.h"
#include "vknerf/error.h"

namespace vknerf::models {

CameraRefinement::CameraRefinement(Context& ctx, uint32_t numCameras, uint32_t rows,
                                   const CameraRefinementSettings& settings, LossReport& report)
    : numCameras_(numCameras),
      penalty_(settings.penalty),
      corrections_(ctx, "cameras", std::vector<float>(size_t(numCameras) * nerf::kCorrectionFloats, 0.0f), settings.adam),
      corrected_(gpu::Buffer::zeros(ctx, VkDeviceSize(std::max(numCameras, 1u)) * sizeof(nerf::CameraGpu),
                                    "the refined cameras")),
      dPosition_(gpu::Buffer::zeros(ctx, VkDeviceSize(rows) * 16, "the samples' position gradients")),
      report_(report),
      kernels_(ctx) {
  if (penalty_ > 0 && numCameras_ > 0) {
    penaltyTerm_ = report.addTerm(LossReport::row("camera_penalty"), false, numCameras_);
    penaltyValues_ = gpu::Buffer::zeros(ctx, VkDeviceSize(numCameras_) * 4, "the cameras' penalties");
  }
}

const gpu::Buffer& CameraRefinement::recordCameras(gpu::Recorder& rec, const TrainingData& data) {
  if (data.numCameras != numCameras_)
    throw Error("fast model: " + std::to_string(data.numCameras) + " training cameras, but camera refinement was set up for " +
                std::to_string(numCameras_));
  kernels_.recordApply(rec, numCameras_, *data.cameras, corrections_.params(), corrected_);
  return corrected_;
}

void CameraRefinement::recordGradient(gpu::Recorder& rec, const StepBatch& b) {
  kernels_.recordGradient(rec, {b.rays, b.pixelIds, b.marchedOffsets, b.rowOffsets, b.marchedSamples, positionGradient_, b.rayCount, b.box},
                          numCameras_, penalty_, corrections_.params(), corrections_.grads(),
                          penaltyTerm_ ? std::optional(gpu::BufferRange(penaltyValues_)) : std::nullopt);
  if (penaltyTerm_) report_.recordTerm(rec, *penaltyTerm_, {penaltyValues_, numCameras_});
}

std::vector<std::array<float, nerf::kCorrectionFloats>> CameraRefinement::corrections() {
  const auto flat = corrections_.params().download<float>(size_t(numCameras_) * nerf::kCorrectionFloats);
  std::vector<std::array<float, nerf::kCorrectionFloats>> out(numCameras_);
  for (size_t i = 0; i < flat.size(); ++i) out[i / nerf::kCorrectionFloats][i % nerf::kCorrectionFloats] = flat[i];
  return out;
}

void CameraRefinement::adjustTrainedCameras(std::vector<Camera>& cameras) {
  const auto all = corrections();
  for (size_t i = 0; i < all.size() && i < cameras.size(); ++i) {
    std::array<double, nerf::kCorrectionFloats> c{};
    for (size_t k = 0; k < c.size(); ++k) c[k] = all[i][k];
    const auto pose = core::correctedPose<double>(cameras[i].c2w, c.data());
    for (int k = 0; k < 16; ++k) cameras[i].c2w[k] = float(pose[k]);
  }
}

}  // namespace vknerf::models

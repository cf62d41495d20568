#include "models/common/camera_refinement.h"

namespace vknerf::models {

CameraRefinement::CameraRefinement(Context& ctx, uint32_t numCameras, const CameraRefinementSettings& settings)
    : numCameras_(numCameras),
      penalty_(settings.penalty),
      corrections_(ctx, "cameras", std::vector<float>(size_t(numCameras) * nerf::kCorrectionFloats, 0.0f), settings.adam),
      corrected_(gpu::Buffer::zeros(ctx, VkDeviceSize(std::max(numCameras, 1u)) * sizeof(nerf::CameraGpu),
                                    "the refined cameras")),
      kernels_(ctx) {}

void CameraRefinement::recordApply(gpu::Recorder& rec, const gpu::Buffer& trainingCameras) {
  kernels_.recordApply(rec, numCameras_, trainingCameras, corrections_.params(), corrected_);
}

void CameraRefinement::recordGradient(gpu::Recorder& rec, const nerf::PoseGradientInputs& in) {
  kernels_.recordGradient(rec, in, numCameras_, penalty_, corrections_.params(), corrections_.grads());
}

std::vector<std::array<float, nerf::kCorrectionFloats>> CameraRefinement::corrections() {
  const auto flat = corrections_.params().download<float>(size_t(numCameras_) * nerf::kCorrectionFloats);
  std::vector<std::array<float, nerf::kCorrectionFloats>> out(numCameras_);
  for (size_t i = 0; i < flat.size(); ++i) out[i / nerf::kCorrectionFloats][i % nerf::kCorrectionFloats] = flat[i];
  return out;
}

}  // namespace vknerf::models

#include "models/common/appearance.h"

#include <string>

#include "vknerf/error.h"

namespace vknerf::nerf {

Appearance::Appearance(Context& ctx, uint32_t numPhotos, uint32_t dims, const std::optional<AdamConfig>& adam,
                       std::optional<uint32_t> renderPhoto)
    : numPhotos_(numPhotos),
      renderPhoto_(renderPhoto),
      table_(ctx, "appearance", std::vector<float>(size_t(numPhotos) * dims, 0.0f), adam),
      mean_(gpu::Buffer::zeros(ctx, VkDeviceSize(dims) * 4, "the mean appearance vector")),
      kernels_(ctx, dims) {
  if (numPhotos == 0) throw Error("appearance embedding: no training photos");
  if (renderPhoto && *renderPhoto >= numPhotos)
    throw Error("render settings: appearance photo " + std::to_string(*renderPhoto) + ", but the model was trained on " +
                std::to_string(numPhotos) + " photos (0.." + std::to_string(numPhotos - 1) + ")");
}

void Appearance::recordTrainingRows(gpu::Recorder& rec, const AppearanceRows& rows) {
  kernels_.recordRows(rec, rows, table_.params());
}

void Appearance::recordRenderRows(gpu::Recorder& rec, AppearanceRows rows) {
  rows.pixelIds.reset(), rows.sampleRay.reset();
  if (renderPhoto_) {
    rows.fixedRow = *renderPhoto_;
    kernels_.recordRows(rec, rows, table_.params());
    return;
  }
  kernels_.recordMean(rec, numPhotos_, table_.params(), mean_);
  rows.fixedRow = 0;
  kernels_.recordRows(rec, rows, mean_);
}

void Appearance::recordGradient(gpu::Recorder& rec, const AppearanceGradientInputs& in) {
  kernels_.recordGradient(rec, in, numPhotos_, table_.grads());
}

}  // namespace vknerf::nerf

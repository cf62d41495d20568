#include "models/common/appearance.h"

#include <string>

#include "core/layouts/appearance_layout.h"
#include "vknerf/error.h"

namespace vknerf::models {

Appearance::Appearance(Context& ctx, uint32_t numPhotos, uint32_t dims, uint32_t width, const AppearanceInit& init,
                       const std::optional<nerf::AdamConfig>& adam, std::optional<uint32_t> renderPhoto, uint32_t rows)
    : numPhotos_(numPhotos),
      renderPhoto_(renderPhoto),
      vectors_(ctx, "appearance", std::vector<float>(size_t(numPhotos) * dims, 0.0f), adam),
      weights_(ctx, "appearance_weights", core::appearanceWeights(dims, width, init.bound, init.seed), adam),
      mean_(gpu::Buffer::zeros(ctx, VkDeviceSize(dims) * 4, "the mean appearance vector")),
      bias_(gpu::Buffer::zeros(ctx, VkDeviceSize(std::max(numPhotos, 1u)) * width * 4, "the appearance biases")),
      photoSums_(gpu::Buffer::zeros(ctx, adam ? VkDeviceSize(std::max(numPhotos, 1u)) * width * 4 : 16)),
      kernels_(ctx, dims, width) {
  if (adam) dColour_ = gpu::Buffer::zeros(ctx, VkDeviceSize(rows) * width * 4, "the samples' colour-layer gradients");
  if (numPhotos == 0) throw Error("appearance embedding: no training photos");
  if (renderPhoto && *renderPhoto >= numPhotos)
    throw Error("render settings: appearance photo " + std::to_string(*renderPhoto) + ", but the model was trained on " +
                std::to_string(numPhotos) + " photos (0.." + std::to_string(numPhotos - 1) + ")");
}

const gpu::Buffer& Appearance::recordCameras(gpu::Recorder&, const TrainingData& data) {
  // The per-photo sums find a photo's rays by the runs the batch was drawn in over data.numCameras.
  if (data.numCameras != numPhotos_)
    throw Error("fast model: " + std::to_string(data.numCameras) + " training photos, but the appearance embedding was set up for " +
                std::to_string(numPhotos_));
  return *data.cameras;
}

std::optional<nerf::RowBias> Appearance::recordColourBias(gpu::Recorder& rec, const StepBatch* batch) {
  if (batch) {
    kernels_.recordBias(rec, parameters(), 0, numPhotos_, bias_);
    return nerf::RowBias{bias_, batch->sampleRay, batch->pixelIds};
  }
  if (renderPhoto_) {
    kernels_.recordBias(rec, parameters(), *renderPhoto_, 1, bias_);
  } else {
    kernels_.recordMean(rec, numPhotos_, vectors_.params(), mean_);
    kernels_.recordBias(rec, {mean_, weights_.params()}, 0, 1, bias_);
  }
  return nerf::RowBias{bias_};
}

void Appearance::recordGradient(gpu::Recorder& rec, const StepBatch& b) {
  kernels_.recordGradient(rec, {b.rays.count, b.pixelIds, b.rowOffsets, colourGradient_, b.rayCount}, numPhotos_, parameters(),
                          {vectors_.grads(), weights_.grads(), photoSums_});
}

void Appearance::recordOptimizerStep(gpu::Recorder& rec, nerf::OptimizerStep at) {
  vectors_.recordOptimizerStep(rec, at);
  weights_.recordOptimizerStep(rec, at);
}

void Appearance::appendState(std::vector<StateArray>& out) {
  vectors_.appendState(out);
  weights_.appendState(out);
}

}  // namespace vknerf::models

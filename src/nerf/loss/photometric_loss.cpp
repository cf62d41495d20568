#include "nerf/loss/photometric_loss.h"

#include <string>
#include <vector>

#include "reference/loss/photometric_loss.h"
#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {
struct LossPush {
  uint32_t numRays;
  float gradScale;
};
}  // namespace

PhotometricLoss::PhotometricLoss(Context& ctx)
    : ctx_(ctx),
      kernel_(ctx, {gpu::shaders::loss_photometric,
                    {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                     gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(LossPush),
                    {}}) {}

void PhotometricLoss::record(gpu::Recorder& rec, uint32_t numRays, const gpu::BufferRange& pred,
                             const gpu::BufferRange& pixelIds, const gpu::BufferRange& images,
                             const gpu::BufferRange& cameras, const gpu::BufferRange& background,
                             const gpu::BufferRange& dPred, const gpu::BufferRange& partials, float gradScale) {
  if (numRays == 0) return;
  VkDeviceSize imageBytes = images.range == VK_WHOLE_SIZE ? images.buffer->size() - images.offset : images.range;
  if (imageBytes > ctx_.properties().limits.maxStorageBufferRange)
    throw Error("PhotometricLoss: " + std::to_string(imageBytes) + " bytes of training pixels exceed this device's " +
                "maxStorageBufferRange (" + std::to_string(ctx_.properties().limits.maxStorageBufferRange) + ")");
  LossPush p{numRays, gradScale};
  rec.dispatch(kernel_, {pred, pixelIds, images, cameras, background, dPred, partials}, p,
               partialCount(numRays), 1, 1, "loss_photometric");
}

LossStats PhotometricLoss::summarize(std::span<const float> partials, uint32_t numRays) {
  if (numRays == 0) return {0, ref::psnrFromMse(0)};
  double sum = 0;
  for (float v : partials) sum += v;
  double mse = sum / (3.0 * numRays);
  return {mse, ref::psnrFromMse(mse)};
}

LossStats PhotometricLoss::read(const gpu::Buffer& partials, uint32_t numRays) const {
  uint32_t n = partialCount(numRays);
  std::vector<float> v = n ? partials.download<float>(n) : std::vector<float>{};
  return summarize(v, numRays);
}

}  // namespace vknerf::nerf

#include "models/common/ray_batch.h"

#include "reference/rng.h"

namespace vknerf::nerf {

uint32_t stepSeed(const TrainConfig& config, uint32_t step) { return ref::pcgHash(config.seed * 7919u + step); }

RayBatch::RayBatch(Context& ctx, uint32_t capacity)
    : capacity_(capacity),
      generation_(ctx),
      backgrounds_(ctx),
      // Zeroed: a recorded render evaluates the field over whole buffers, never over garbage.
      rays_(gpu::Buffer::zeros(ctx, VkDeviceSize(capacity) * kRayBytes)),
      pixelIds_(gpu::Buffer::zeros(ctx, VkDeviceSize(capacity) * kPixelIdBytes)),
      background_(gpu::Buffer::zeros(ctx, VkDeviceSize(capacity) * 16)) {}

void RayBatch::recordTraining(gpu::Recorder& rec, const TrainingData& data, uint32_t seed, uint32_t count,
                              const Aabb& box, const TrainConfig& config) {
  generation_.recordRandom(rec, count, *data.cameras, data.numCameras, seed, box, kNearPlane, rays_, pixelIds_);
  if (config.randomBackground && data.transparentPixels)
    backgrounds_.recordRandom(rec, background_, count, seed);
  else
    backgrounds_.recordConstant(rec, background_, count, config.background);
}

void RayBatch::recordView(gpu::Recorder& rec, const gpu::BufferRange& cameras, uint32_t camera, uint32_t first,
                          uint32_t count, const Aabb& box, const std::array<float, 3>& background) {
  generation_.recordImage(rec, count, cameras, camera, first, box, kNearPlane, rays_, pixelIds_);
  backgrounds_.recordConstant(rec, background_, count, background);
}

}  // namespace vknerf::nerf

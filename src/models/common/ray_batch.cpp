#include "models/common/ray_batch.h"

#include <string>

#include "gpu/device/device.h"
#include "core/math/rng.h"
#include "vknerf/error.h"

namespace vknerf::models {

uint32_t stepSeed(const TrainConfig& config, uint32_t step) { return core::pcgHash(config.seed * 7919u + step); }

namespace {
// The ray generator binds a batch's rays as one range: a batch larger than the device's binding
// limit is a configuration error, said before anything is allocated.
uint32_t checkedCapacity(Context& ctx, uint32_t capacity) {
  const uint64_t limit = gpu::device(ctx).properties().limits.maxStorageBufferRange;
  if (uint64_t(capacity) * nerf::kRayBytes > limit)
    throw Error("a batch of " + std::to_string(capacity) + " rays needs " + std::to_string(uint64_t(capacity) * nerf::kRayBytes) +
                " bytes of rays in one binding, over this device's maxStorageBufferRange (" + std::to_string(limit) +
                "): at most " + std::to_string(limit / nerf::kRayBytes) + " rays per batch");
  return capacity;
}
}  // namespace

RayBatch::RayBatch(Context& ctx, uint32_t capacity, float nearPlane, bool inCameraRuns)
    : capacity_(checkedCapacity(ctx, capacity)),
      nearPlane_(nearPlane),
      inCameraRuns_(inCameraRuns),
      generation_(ctx),
      backgrounds_(ctx),
      // Zeroed: a recorded render evaluates the field over whole buffers, never over garbage.
      rays_(gpu::Buffer::zeros(ctx, VkDeviceSize(capacity) * nerf::kRayBytes, "the rays of a batch")),
      pixelIds_(gpu::Buffer::zeros(ctx, VkDeviceSize(capacity) * nerf::kPixelIdBytes, "the pixel ids of a batch")),
      background_(gpu::Buffer::zeros(ctx, VkDeviceSize(capacity) * 16, "the backgrounds of a batch")) {}

void RayBatch::recordTraining(gpu::Recorder& rec, const TrainingData& data, uint32_t seed, uint32_t count,
                              const Aabb& box, const TrainConfig& config) {
  generation_.recordRandom(rec, *data.cameras, {data.numCameras, seed, count, inCameraRuns_}, {box, nearPlane_}, {rays_, pixelIds_});
  if (config.randomBackground)
    backgrounds_.recordRandom(rec, background_, count, seed);
  else
    backgrounds_.recordConstant(rec, background_, count, config.background);
}

void RayBatch::recordView(gpu::Recorder& rec, const ViewBlock& view, const Aabb& box) {
  generation_.recordImage(rec, view.cameras, {view.camera, view.first, view.count}, {box, nearPlane_},
                          {rays_, pixelIds_});
  backgrounds_.recordConstant(rec, background_, view.count, view.background);
}

}  // namespace vknerf::models

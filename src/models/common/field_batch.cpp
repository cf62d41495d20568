#include "models/common/field_batch.h"

#include "nerf/render/composite.h"
#include "nerf/sampling/points.h"

namespace vknerf::nerf {

FieldBatch::FieldBatch(Context& ctx, const NerfMlp& mlp, uint32_t n, bool training)
    : capacity(n),
      positions(gpu::Buffer::zeros(ctx, VkDeviceSize(n) * kPointBytes)),
      directions(gpu::Buffer::zeros(ctx, VkDeviceSize(n) * kPointBytes)),
      posFeatures(gpu::Buffer::zeros(ctx, VkDeviceSize(n) * mlp.posStride() * sizeof(float))),
      dirFeatures(gpu::Buffer::zeros(ctx, VkDeviceSize(n) * mlp.dirStride() * sizeof(float))),
      field(gpu::Buffer::zeros(ctx, VkDeviceSize(n) * kFieldBytes)) {
  if (!training) return;
  dField = gpu::Buffer::zeros(ctx, VkDeviceSize(n) * kFieldBytes);
  workspace = std::make_unique<NerfMlp::Workspace>(ctx, mlp, n);
}

}  // namespace vknerf::nerf

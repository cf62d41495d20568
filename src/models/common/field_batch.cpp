#include "models/common/field_batch.h"

#include "nerf/render/composite.h"
#include "nerf/sampling/points.h"

namespace vknerf::models {

FieldBatch::FieldBatch(Context& ctx, const nerf::NerfMlp& mlp, uint32_t n, bool training)
    : capacity(n),
      positions(gpu::Buffer::zeros(ctx, VkDeviceSize(n) * nerf::kPointBytes, "the sample positions")),
      directions(gpu::Buffer::zeros(ctx, VkDeviceSize(n) * nerf::kPointBytes, "the sample directions")),
      posFeatures(gpu::Buffer::zeros(ctx, VkDeviceSize(n) * mlp.posStride() * sizeof(float), "the position encodings")),
      dirFeatures(gpu::Buffer::zeros(ctx, VkDeviceSize(n) * mlp.dirStride() * sizeof(float), "the direction encodings")),
      field(gpu::Buffer::zeros(ctx, VkDeviceSize(n) * nerf::kFieldBytes, "the field values per sample")) {
  if (!training) return;
  dField = gpu::Buffer::zeros(ctx, VkDeviceSize(n) * nerf::kFieldBytes, "the field gradients per sample");
  workspace = std::make_unique<nerf::NerfMlp::Workspace>(ctx, mlp, n);
}

}  // namespace vknerf::models

#include "nerf/sampling/kept_rows.h"

#include <algorithm>
#include <string>

#include "vknerf/error.h"
#include "sampling/kept_rows_shared.h"

namespace vknerf::nerf {
namespace {
constexpr uint32_t kLocal = 64;
using Push = glsl::KeptRowsPush;
}  // namespace

KeptRows::KeptRows(Context& ctx, uint32_t maxRays, uint32_t sampleCapacity)
    : maxRays_(maxRays),
      capacity_(sampleCapacity),
      layout_(ctx, maxRays),
      offsets_(ctx, (VkDeviceSize(maxRays) + 1) * 4),
      totals_(gpu::Buffer::zeros(ctx, PackedLayout::kTotalsBytes)),
      rows_(ctx, VkDeviceSize(std::max(sampleCapacity, 1u)) * 4, "the kept samples' rows"),
      positions_(ctx, VkDeviceSize(std::max(sampleCapacity, 1u)) * 16, "the kept samples' positions"),
      kernel_(ctx, {gpu::shaders::kept_rows,
                    {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::TexelRgba32f, gpu::Binding::Storage,
                     gpu::Binding::Storage},
                    sizeof(Push),
                    {}}) {}

void KeptRows::record(gpu::Recorder& rec, uint32_t numRays, const gpu::BufferRange& rayOffsets,
                      const gpu::BufferRange& positions) {
  if (numRays > maxRays_)
    throw Error("KeptRows: " + std::to_string(numRays) + " rays, over the " + std::to_string(maxRays_) +
                " it was built for");
  gpu::requireBytes("KeptRows", "rayOffsets", rayOffsets, (uint64_t(numRays) + 1) * 4);
  gpu::requireBytes("KeptRows", "positions", positions, uint64_t(capacity_) * 16);
  if (numRays == 0) return;
  recordTotal(rec, numRays);
  rec.dispatch(kernel_, {rayOffsets, offsets_, positions, rows_, positions_}, Push{numRays},
               gpu::groupsFor(numRays, kLocal), 1, 1, "kept_rows");
}

void KeptRows::recordTotal(gpu::Recorder& rec, uint32_t numRays) {
  if (numRays > maxRays_)
    throw Error("KeptRows: " + std::to_string(numRays) + " rays, over the " + std::to_string(maxRays_) +
                " it was built for");
  if (numRays == 0) return rec.fill(totals_, 0, 0, 4);
  layout_.recordOffsetsAndTotals(rec, numRays, capacity_, offsets_, totals_);
}

}  // namespace vknerf::nerf

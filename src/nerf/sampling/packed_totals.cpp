#include "nerf/sampling/packed_totals.h"

#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {
struct TotalsPush {
  uint32_t numRays, localSize, maxGroupsX;
};
}  // namespace

PackedTotals::PackedTotals(Context& ctx)
    : ctx_(ctx),
      kernel_(ctx, {gpu::shaders::march_totals, {gpu::Binding::Storage, gpu::Binding::Storage}, sizeof(TotalsPush), {}}) {}

void PackedTotals::record(gpu::Recorder& rec, const gpu::BufferRange& offsets, uint32_t numRays, uint32_t localSize,
                          const gpu::BufferRange& totals) {
  if (localSize == 0) throw Error("RayMarcher: dispatch local size must be at least 1");
  gpu::requireBytes("RayMarcher", "offsets", offsets, (uint64_t(numRays) + 1) * 4);
  gpu::requireBytes("RayMarcher", "totals", totals, kBytes);
  TotalsPush p{numRays, localSize, ctx_.properties().limits.maxComputeWorkGroupCount[0]};
  rec.dispatch(kernel_, {offsets, totals}, p, 1, 1, 1, "march_totals");
}

}  // namespace vknerf::nerf

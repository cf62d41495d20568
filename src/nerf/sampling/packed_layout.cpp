#include "nerf/sampling/packed_layout.h"

#include <algorithm>

#include "vknerf/error.h"
#include "sampling/march_totals_shared.h"
#include "sampling/march_cut_shared.h"

namespace vknerf::nerf {
namespace {
using TotalsPush = glsl::MarchTotalsPush;
using CutPush = glsl::MarchCutPush;
}  // namespace

PackedLayout::PackedLayout(Context& ctx, uint32_t maxRays)
    : ctx_(ctx),
      counts_(ctx, VkDeviceSize(std::max(maxRays, 1u)) * 4),
      scan_(ctx, maxRays + 1),
      totals_(ctx, {gpu::shaders::march_totals, {gpu::Binding::Storage, gpu::Binding::Storage}, sizeof(TotalsPush), {}}) {}

void PackedLayout::requireOutputs(const char* stage, uint32_t numRays, const gpu::BufferRange& offsets,
                                  const gpu::BufferRange& totals) {
  gpu::requireBytes(stage, "offsets", offsets, (uint64_t(numRays) + 1) * 4);
  gpu::requireBytes(stage, "totals", totals, kTotalsBytes);
}

void PackedLayout::recordOffsetsAndTotals(gpu::Recorder& rec, uint32_t numRays, uint32_t capacity,
                                          const gpu::BufferRange& offsets, const gpu::BufferRange& totals) {
  requireOutputs("PackedLayout", numRays, offsets, totals);
  scan_.record(rec, counts_, numRays, offsets, numRays + 1, capacity);
  TotalsPush p{numRays, kIndirectLocal, ctx_.properties().limits.maxComputeWorkGroupCount[0]};
  rec.dispatch(totals_, {offsets, totals}, p, 1, 1, 1, "march_totals");
}

void PackedLayout::recordCutToWholeRays(gpu::Recorder& rec, const PackedCut& cut, const PackedSamples& batch,
                                        const gpu::BufferRange& wholeRays) {
  const uint32_t numRays = cut.numRays, capacity = cut.capacity, rayAlign = cut.rayAlign;
  const gpu::BufferRange &offsets = batch.offsets, &totals = batch.totals;
  requireOutputs("PackedLayout::recordCutToWholeRays", numRays, offsets, totals);
  gpu::requireBytes("PackedLayout::recordCutToWholeRays", "wholeRays", wholeRays, 4);
  if (rayAlign == 0) throw Error("PackedLayout::recordCutToWholeRays: rayAlign must be positive");
  if (!cut_)
    cut_ = std::make_unique<gpu::Kernel>(
        ctx_, gpu::KernelDesc{gpu::shaders::march_cut, {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                              sizeof(CutPush), {}});
  CutPush p{numRays, kIndirectLocal, ctx_.properties().limits.maxComputeWorkGroupCount[0], capacity, rayAlign};
  rec.dispatch(*cut_, {offsets, totals, wholeRays}, p, 1, 1, 1, "march_cut");
}

}  // namespace vknerf::nerf

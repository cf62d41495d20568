#include "nerf/sampling/segment_rows.h"

#include <algorithm>
#include <string>

#include "vknerf/error.h"
#include "nerf/sampling/sample_layout.h"
#include "sampling/segment_rows_shared.h"

namespace vknerf::nerf {
namespace {
constexpr uint32_t kLocal = 64;
using Push = glsl::SegmentRowsPush;
}  // namespace

SegmentRows::SegmentRows(Context& ctx, uint32_t sampleCapacity)
    : capacity_(sampleCapacity),
      rows_(ctx, VkDeviceSize(std::max(sampleCapacity, 1u)) * 4, "the forward's segment rows"),
      count_(gpu::Buffer::zeros(ctx, 4)),
      kernel_(ctx, {gpu::shaders::segment_rows,
                    {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::TexelRgba32f, gpu::Binding::Storage,
                     gpu::Binding::Storage},
                    sizeof(Push),
                    {}}) {}

void SegmentRows::record(gpu::Recorder& rec, uint32_t numRays, const PackedSamples& batch,
                         const gpu::BufferRange& field, float maxOpticalDepth, uint32_t from, uint32_t to) {
  if (from >= to)
    throw Error("SegmentRows: the segment [" + std::to_string(from) + ", " + std::to_string(to) + ") is empty");
  gpu::requireBytes("SegmentRows", "ray offsets", batch.offsets, (uint64_t(numRays) + 1) * 4);
  gpu::requireBytes("SegmentRows", "samples", batch.samples, uint64_t(capacity_) * kSampleBytes);
  gpu::requireBytes("SegmentRows", "field", field, uint64_t(capacity_) * 16);
  rec.fill(count_, 0);
  if (numRays == 0) return;
  rec.dispatch(kernel_, {batch.offsets, batch.samples, field, rows_, count_}, Push{numRays, from, to, maxOpticalDepth},
               gpu::groupsFor(numRays, kLocal), 1, 1, "segment_rows");
}

}  // namespace vknerf::nerf

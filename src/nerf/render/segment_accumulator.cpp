#include "nerf/render/segment_accumulator.h"

#include <string>

#include "vknerf/error.h"
#include "render/accumulate_segment_shared.h"

namespace vknerf::nerf {
namespace {
constexpr uint32_t kLocal = 64;  // accumulate_segment.comp
using Push = glsl::SegmentPush;
}  // namespace

SegmentAccumulator::SegmentAccumulator(Context& ctx, uint32_t maxRays)
    : maxRays_(maxRays),
      segmentColor_(gpu::Buffer::zeros(ctx, VkDeviceSize(std::max(maxRays, 1u)) * 16)),
      segmentDepth_(gpu::Buffer::zeros(ctx, VkDeviceSize(std::max(maxRays, 1u)) * 4)),
      counters_(gpu::Buffer::zeros(ctx, 16)),
      kernel_(ctx, {gpu::shaders::accumulate_segment,
                    {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                     gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                     gpu::Binding::Storage},
                    sizeof(Push),
                    {}}) {}

void SegmentAccumulator::recordResetCounts(gpu::Recorder& rec) { rec.fill(counters_, 0, 0, 8); }

void SegmentAccumulator::record(gpu::Recorder& rec, const Round& round, const RaySpan& raySpan,
                                const PackedSamples& batch, const Gathered& gathered) {
  const uint32_t numRays = raySpan.count;
  const gpu::BufferRange &rays = raySpan.range, &rayOffsets = batch.offsets, &samples = batch.samples;
  const gpu::BufferRange &background = gathered.background, &color = gathered.color, &depth = gathered.depth;
  if (numRays > maxRays_)
    throw Error("SegmentAccumulator: " + std::to_string(numRays) + " rays, over the " + std::to_string(maxRays_) +
                " it was built for");
  if (round.cap == 0) throw Error("SegmentAccumulator: a round's cap must be > 0");
  const uint64_t n = numRays;
  gpu::requireBytes("SegmentAccumulator", "rays", rays, n * 32);
  gpu::requireBytes("SegmentAccumulator", "rayOffsets", rayOffsets, (n + 1) * 4);
  gpu::requireBytes("SegmentAccumulator", "background", background, n * 16);
  gpu::requireBytes("SegmentAccumulator", "color", color, n * 16);
  gpu::requireBytes("SegmentAccumulator", "depth", depth, n * 4);
  if (numRays == 0) return;
  const Push p{numRays, round.cap, round.first ? 1u : 0u, round.last ? 1u : 0u, round.minTransmittance};
  rec.dispatch(kernel_,
               {rays, rayOffsets, samples, gpu::BufferRange(segmentColor_, 0, n * 16),
                gpu::BufferRange(segmentDepth_, 0, n * 4), background, color, depth, counters_},
               p, gpu::groupsFor(numRays, kLocal), 1, 1, "accumulate_segment");
}

uint32_t SegmentAccumulator::active() const { return counters_.download<uint32_t>(1)[0]; }
uint32_t SegmentAccumulator::samples() const { return counters_.download<uint32_t>(2)[1]; }

}  // namespace vknerf::nerf

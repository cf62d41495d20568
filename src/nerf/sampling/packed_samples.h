#pragma once
// A packed batch of samples as one value (nerfacc's packed RaySamples): RayMarcher writes it,
// PackedSamplePoints, Compositor (samplesPerRay = 0), SegmentAccumulator and KeptRows read it.
//   offsets    uint[numRays + 1]: ray r owns samples [off[r], off[r+1]) (nerf::PackedLayout)
//   samples    vec2 (t, delta) per sample (nerf::kSampleBytes)
//   sampleRay  uint per sample: the ray it belongs to
//   totals     uint[4] (PackedLayout::kTotalsBytes): the sample total, then the indirect dispatch
#include "gpu/memory/buffer.h"

namespace vknerf::nerf {

struct PackedSamples {
  gpu::BufferRange offsets, samples, sampleRay, totals;

  // The sample total alone, the first uint of the totals: what the per-sample kernels are cut to
  // (gpu/dispatch/limited_dispatch.h).
  gpu::BufferRange total() const { return gpu::BufferRange(*totals.buffer, totals.offset, sizeof(uint32_t)); }
};

}  // namespace vknerf::nerf

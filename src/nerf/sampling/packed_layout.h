#pragma once
// The layout every stage that packs samples writes (RayMarcher): a first pass
// counts each ray's samples into counts(), then recordOffsetsAndTotals turns the counts into
//   offsets uint[numRays + 1]: ray r owns samples [off[r], off[r+1]); an exclusive prefix sum of the
//           counts, clamped at the sample capacity so that off[numRays] <= capacity always
//   totals  uint[4]: [0] = offsets[numRays], the total samples; [1..3] = a VkDispatchIndirectCommand
//           covering the total with workgroups of kIndirectLocal (x capped at the device limit, the
//           rest in y: per-sample kernels index flatly, as sampling.glsl's flatInvocation() does)
// (shaders/gpu/scan_*.comp, shaders/sampling/march_totals.comp); a second pass then writes the
// samples at their offsets.
#include <cstdint>
#include <memory>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/prefix_sum.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/sampling/packed_samples.h"

namespace vknerf::nerf {

// How a batch packed at a sample capacity is cut to its whole rays (PackedLayout::recordCutToWholeRays).
struct PackedCut {
  uint32_t numRays = 0;   // the rays the batch was packed for
  uint32_t capacity = 0;  // the samples it was packed at
  uint32_t rayAlign = 1;  // the rays kept are a multiple of this
};

class PackedLayout {
 public:
  static constexpr uint32_t kIndirectLocal = 64;  // the local size of the batches' per-sample kernels
  static constexpr VkDeviceSize kTotalsBytes = 16;

  PackedLayout(Context& ctx, uint32_t maxRays);
  // uint per ray: what the counting pass writes.
  const gpu::Buffer& counts() const { return counts_; }
  gpu::Buffer& counts() { return counts_; }
  // Throws vknerf::Error for buffers too small for numRays; a stage checks them with
  // requireOutputs before it records anything, so that a bad call leaves nothing half recorded.
  static void requireOutputs(const char* stage, uint32_t numRays, const gpu::BufferRange& offsets,
                             const gpu::BufferRange& totals);
  void recordOffsetsAndTotals(gpu::Recorder& rec, uint32_t numRays, uint32_t capacity,
                              const gpu::BufferRange& offsets, const gpu::BufferRange& totals);
  // After a batch was packed at cut.capacity: keeps its whole rays on the device (all of them when
  // the batch is under the capacity; else those ending below it, rounded down to a multiple of
  // cut.rayAlign, at least rayAlign), empties the offsets of the rest at the kept total, rewrites the
  // totals for the kept samples and writes the rays kept as the uint `wholeRays`
  // (shaders/sampling/march_cut.comp). Only the batch's offsets and totals are read and written.
  void recordCutToWholeRays(gpu::Recorder& rec, const PackedCut& cut, const PackedSamples& batch,
                            const gpu::BufferRange& wholeRays);

 private:
  Context& ctx_;
  gpu::Buffer counts_;
  gpu::PrefixSum scan_;
  gpu::Kernel totals_;
  std::unique_ptr<gpu::Kernel> cut_;  // built on first use (training only)
};

}  // namespace vknerf::nerf

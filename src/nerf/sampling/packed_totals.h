#pragma once
// The totals of a packed sample batch (shaders/sampling/march_totals.comp), written after the
// offsets by every stage that packs samples (RayMarcher, EarlyTermination):
//   totals  uint[4]: [0] = offsets[numRays], the total samples; [1..3] = a VkDispatchIndirectCommand
//           covering the total with workgroups of `localSize` (x capped at the device limit, the
//           rest in y: per-sample kernels index flatly, as sampling.glsl's flatInvocation() does)
#include <cstdint>

#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu/recorder.h"

namespace vknerf::nerf {

class PackedTotals {
 public:
  static constexpr uint32_t kIndirectLocal = 64;  // the local size of the batches' per-sample kernels
  static constexpr VkDeviceSize kBytes = 16;

  explicit PackedTotals(Context& ctx);
  // Throws vknerf::Error for localSize == 0 or buffers too small for numRays.
  void record(gpu::Recorder& rec, const gpu::BufferRange& offsets, uint32_t numRays, uint32_t localSize,
              const gpu::BufferRange& totals);

 private:
  Context& ctx_;
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

#pragma once
// Partial sums of a float per item (shaders/loss/sum_partials.comp): one per group of kPerPartial
// items, summed in shared memory (no float atomics); the host adds them in double. What a loss
// term's value is reported through (models/common/loss_report.h): a step sums its per-ray or
// per-camera values on the device, and the host reads a few floats.
#include <cstdint>

#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"

namespace vknerf::nerf {

// `count` values, value i at float i * stride + component of `values`.
struct SummedValues {
  gpu::BufferRange values;
  uint32_t count = 0, stride = 1, component = 0;
};

class PartialSums {
 public:
  static constexpr uint32_t kPerPartial = 128;  // the shader's workgroup size
  static uint32_t partialCount(uint32_t count) { return gpu::groupsFor(count, kPerPartial); }

  explicit PartialSums(Context& ctx);
  // partials[g] = the sum of values [g kPerPartial, (g + 1) kPerPartial), for partialCount(count) floats.
  void record(gpu::Recorder& rec, const SummedValues& in, const gpu::BufferRange& partials);

 private:
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

#pragma once
// Exclusive prefix sum of uints on the device (shaders/gpu/scan_blocks.comp, scan_add.comp): the
// packed sample layouts of the marcher and the hash encoding's sorted backward are built on it.
#include <cstdint>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"

namespace vknerf::gpu {

// out[i] = min(sum_{j<i} in[j], clampTo) for i < outputCount, with in[j] = 0 for j >= inputCount
// (so n counts scanned into n + 1 outputs end with the total). Sums must not overflow 32 bits.
// Scratch for up to maxCount outputs is allocated once.
class PrefixSum {
 public:
  PrefixSum(Context& ctx, uint32_t maxCount);
  void record(Recorder& rec, const BufferRange& input, uint32_t inputCount, const BufferRange& output,
              uint32_t outputCount, uint32_t clampTo = 0xffffffffu);
  uint32_t maxCount() const { return maxCount_; }

 private:
  // What one level scans: inputCount uints of input into outputCount uints of output.
  struct Pass {
    BufferRange input;
    uint32_t inputCount = 0;
    BufferRange output;
    uint32_t outputCount = 0;
  };
  void recordLevel(Recorder& rec, const Pass& pass, uint32_t clampTo, size_t level);
  uint32_t maxCount_;
  std::vector<Buffer> blockSums_, blockOffsets_;  // one pair per level above the first
  Buffer dummy_;
  Kernel blocks_, add_;
};

}  // namespace vknerf::gpu

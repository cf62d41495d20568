#include "gpu/dispatch/prefix_sum.h"

#include <string>

#include "vknerf/error.h"
#include "gpu/scan_blocks_shared.h"
#include "gpu/scan_add_shared.h"

namespace vknerf::gpu {
namespace {

using BlocksPush = glsl::ScanBlocksPush;
using AddPush = glsl::ScanAddPush;

constexpr uint32_t kScanBlock = 1024, kAddLocal = 256;

uint32_t blocksFor(uint32_t n) { return (n + kScanBlock - 1) / kScanBlock; }

}  // namespace

PrefixSum::PrefixSum(Context& ctx, uint32_t maxCount)
    : maxCount_(maxCount),
      dummy_(ctx, 16),
      blocks_(ctx, {shaders::scan_blocks, {Binding::Storage, Binding::Storage, Binding::Storage}, sizeof(BlocksPush), {}}),
      add_(ctx, {shaders::scan_add, {Binding::Storage, Binding::Storage}, sizeof(AddPush), {}}) {
  // scan_add covers a level with one x-dispatch of 256-wide groups.
  uint64_t maxAdd = uint64_t(ctx.properties().limits.maxComputeWorkGroupCount[0]) * kAddLocal;
  if (maxCount > maxAdd)
    throw Error("PrefixSum: " + std::to_string(maxCount) + " elements exceed one dispatch (" + std::to_string(maxAdd) + ")");
  for (uint32_t n = blocksFor(maxCount); n > 1; n = blocksFor(n)) {
    blockSums_.emplace_back(ctx, VkDeviceSize(n) * 4);
    blockOffsets_.emplace_back(ctx, VkDeviceSize(n) * 4);
  }
}

void PrefixSum::record(Recorder& rec, const BufferRange& input, uint32_t inputCount, const BufferRange& output,
                       uint32_t outputCount, uint32_t clampTo) {
  if (outputCount > maxCount_)
    throw Error("PrefixSum: " + std::to_string(outputCount) + " outputs exceed the capacity " + std::to_string(maxCount_));
  requireBytes("PrefixSum", "input", input, uint64_t(inputCount) * 4);
  requireBytes("PrefixSum", "output", output, uint64_t(outputCount) * 4);
  recordLevel(rec, {input, inputCount, output, outputCount}, clampTo, 0);
}

// One block: scanned and clamped in place. More: block totals, their scan (recursively), and the
// scanned totals added back, clamping only there, where the sums are final.
void PrefixSum::recordLevel(Recorder& rec, const Pass& pass, uint32_t clampTo, size_t level) {
  const BufferRange &input = pass.input, &output = pass.output;
  const uint32_t inputCount = pass.inputCount, outputCount = pass.outputCount;
  uint32_t blocks = blocksFor(outputCount);
  if (blocks <= 1) {
    BlocksPush p{inputCount, outputCount, clampTo, 0};
    rec.dispatch(blocks_, {input, output, dummy_}, p, blocks, 1, 1, "scan_blocks");
    return;
  }
  BlocksPush p{inputCount, outputCount, 0xffffffffu, 1};
  rec.dispatch(blocks_, {input, output, blockSums_[level]}, p, blocks, 1, 1, "scan_blocks");
  recordLevel(rec, {blockSums_[level], blocks, blockOffsets_[level], blocks}, 0xffffffffu, level + 1);
  AddPush a{outputCount, clampTo};
  rec.dispatch(add_, {output, blockOffsets_[level]}, a, groupsFor(outputCount, kAddLocal), 1, 1, "scan_add");
}

}  // namespace vknerf::gpu

#pragma once
// Dispatches cut to a row count that only the device knows (shaders/row_limit.glsl,
// shaders/limited_dispatch_args.comp): a batch recorded for a capacity, e.g. the field of a fast
// model's render recorded into a caller's command buffer, where the sample count comes from the
// march in the same command buffer. The kernels bind the limit word and skip rows past it; their
// workgroup counts come from arguments written on the device, so idle workgroups are not launched.
#include <initializer_list>
#include <memory>

#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu/recorder.h"

namespace vknerf::gpu {

// ROW_LIMIT_NONE in shaders/row_limit.glsl: the push constant `limitBase` of an unlimited dispatch.
constexpr uint32_t kNoRowLimit = 0xffffffffu;

// One dispatch of a limited batch: the limit word the kernel binds, the dispatch's first row in the
// batch (its push constant `limitBase`), and where its indirect arguments are.
struct LimitedRows {
  BufferRange limit;
  uint32_t base = 0;
  const Buffer* args = nullptr;
  VkDeviceSize argsOffset = 0;
};

class LimitedDispatch {
 public:
  static constexpr uint32_t kMaxEntries = 1024;
  explicit LimitedDispatch(Context& ctx) : ctx_(ctx) {}

  // Records the arguments of a `count`-row batch split into chunks of `chunkRows`, for kernels of
  // the given rows per workgroup (1..4 kinds); `limit` is a uint on the device. The arguments are
  // overwritten by the next call: record their dispatches before it (Recorder orders commands).
  void recordArgs(Recorder& rec, const BufferRange& limit, uint32_t count, uint32_t chunkRows,
                  std::initializer_list<uint32_t> rowsPerGroup);
  // The dispatch of chunk `chunk` for kind `kind` (the order given to recordArgs).
  LimitedRows rows(uint32_t chunk, uint32_t kind) const;

 private:
  Context& ctx_;
  std::unique_ptr<Kernel> kernel_;  // built on first use: unlimited users never pay its JIT
  std::unique_ptr<Buffer> args_;
  BufferRange limit_;
  uint32_t chunkRows_ = 0, kinds_ = 0, chunks_ = 0;
};

}  // namespace vknerf::gpu

#pragma once
// Dispatches cut to a row count that only the device knows (shaders/gpu/row_limit.glsl,
// shaders/gpu/limited_dispatch_args.comp): a batch recorded for a capacity, e.g. the field of a fast
// model's render recorded into a caller's command buffer, where the sample count comes from the
// march in the same command buffer. The kernels bind the limit word and skip rows past it; their
// workgroup counts come from arguments written on the device, so idle workgroups are not launched.
// The same kernels run uncut too: they then bind a placeholder (never read) and get kNoRowLimit.
#include <initializer_list>
#include <memory>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"

namespace vknerf::gpu {

// ROW_LIMIT_NONE in shaders/gpu/row_limit.glsl: the push constant `limitBase` of an uncut dispatch.
constexpr uint32_t kNoRowLimit = 0xffffffffu;

// One dispatch of a batch: the binding for the kernel's row limit (the limit word, or a placeholder
// when uncut), the dispatch's first row in the batch (its push constant `limitBase`, kNoRowLimit
// when uncut), and where its indirect arguments are (none when uncut: dispatched directly).
struct LimitedRows {
  BufferRange limit;
  uint32_t base = kNoRowLimit;
  const Buffer* args = nullptr;
  VkDeviceSize argsOffset = 0;
};

class LimitedDispatch {
 public:
  static constexpr uint32_t kMaxEntries = 1024;
  explicit LimitedDispatch(Context& ctx);

  // Starts a `count`-row batch dispatched in chunks of `chunkRows`: cut to `*limit` (a uint on the
  // device) when given, with its arguments recorded here for kernels of the given rows per
  // workgroup (1..4 kinds); uncut when null. rows() answers for this batch until the next begin.
  void begin(Recorder& rec, const BufferRange* limit, uint32_t count, uint32_t chunkRows,
             std::initializer_list<uint32_t> rowsPerGroup);
  // Records the arguments of a `count`-row batch split into chunks of `chunkRows`, for kernels of
  // the given rows per workgroup (1..4 kinds); `limit` is a uint on the device. The arguments are
  // overwritten by the next call: record their dispatches before it (Recorder orders commands).
  void recordArgs(Recorder& rec, const BufferRange& limit, uint32_t count, uint32_t chunkRows,
                  std::initializer_list<uint32_t> rowsPerGroup);
  // The dispatch of chunk `chunk` for kind `kind` (the order given to recordArgs); uncut() after a
  // begin without a limit.
  LimitedRows rows(uint32_t chunk, uint32_t kind) const;
  LimitedRows uncut() const { return {*none_}; }

 private:
  Context& ctx_;
  std::unique_ptr<Kernel> kernel_;  // built on first use: uncut users never pay its JIT
  std::unique_ptr<Buffer> args_;
  std::unique_ptr<Buffer> none_;    // bound as the row limit of uncut dispatches (never read)
  BufferRange limit_;
  uint32_t chunkRows_ = 0, kinds_ = 0, chunks_ = 0;
  bool cut_ = false;
};

// One dispatch of a kernel that may be cut (row_limit.glsl): `bindings` and then the row limit
// `rows.limit` (the kernel's last binding, ROW_LIMIT_BINDING); indirect when cut, else `groups`
// workgroups. Sets push.limitBase.
void dispatchLimited(Recorder& rec, Kernel& k, std::initializer_list<BufferRange> bindings, const void* push,
                     uint32_t pushBytes, const LimitedRows& rows, uint32_t groups, const char* label);
template <class P>
void dispatchLimited(Recorder& rec, Kernel& k, std::initializer_list<BufferRange> bindings, P push,
                     const LimitedRows& rows, uint32_t groups, const char* label) {
  push.limitBase = rows.base;
  dispatchLimited(rec, k, bindings, &push, sizeof push, rows, groups, label);
}

}  // namespace vknerf::gpu

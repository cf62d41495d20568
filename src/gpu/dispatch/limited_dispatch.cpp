#include "gpu/dispatch/limited_dispatch.h"

#include <string>
#include <vector>

#include "vknerf/error.h"
#include "gpu/limited_dispatch_args_shared.h"

namespace vknerf::gpu {
namespace {
using ArgsPush = glsl::LimitedDispatchArgsPush;
}  // namespace

LimitedDispatch::LimitedDispatch(Context& ctx) : ctx_(ctx), none_(std::make_unique<Buffer>(ctx, 16)) {}

void LimitedDispatch::begin(Recorder& rec, const BufferRange* limit, uint32_t count, uint32_t chunkRows,
                            std::initializer_list<uint32_t> rowsPerGroup) {
  cut_ = limit != nullptr;
  if (cut_) recordArgs(rec, *limit, count, chunkRows, rowsPerGroup);
}

void LimitedDispatch::recordArgs(Recorder& rec, const BufferRange& limit, uint32_t count, uint32_t chunkRows,
                                 std::initializer_list<uint32_t> rowsPerGroup) {
  if (boundBytes(limit) < 4) throw Error("row limit binding holds no uint");
  if (chunkRows == 0 || rowsPerGroup.size() == 0 || rowsPerGroup.size() > 4)
    throw Error("LimitedDispatch: chunk rows must be positive, kinds 1..4");
  ArgsPush p{count, chunkRows, uint32_t((uint64_t(count) + chunkRows - 1) / chunkRows), uint32_t(rowsPerGroup.size()), {1, 1, 1, 1}};
  uint32_t k = 0;
  for (uint32_t r : rowsPerGroup) {
    if (r == 0) throw Error("LimitedDispatch: rows per workgroup must be positive");
    p.rowsPerGroup[k++] = r;
  }
  if (uint64_t(p.chunks) * p.kinds > kMaxEntries)
    throw Error("LimitedDispatch: " + std::to_string(p.chunks) + " chunks of " + std::to_string(p.kinds) +
                " dispatches exceed " + std::to_string(kMaxEntries) + " entries");
  if (!kernel_) {
    kernel_ = std::make_unique<Kernel>(ctx_, KernelDesc{gpu::shaders::limited_dispatch_args, {Binding::Storage, Binding::Storage},
                                                        sizeof(ArgsPush), {}});
    args_ = std::make_unique<Buffer>(ctx_, VkDeviceSize(kMaxEntries) * 12);
  }
  limit_ = limit, chunkRows_ = chunkRows, kinds_ = p.kinds, chunks_ = p.chunks, cut_ = true;
  rec.dispatch(*kernel_, {limit, *args_}, p, groupsFor(uint64_t(p.chunks) * p.kinds, 64), 1, 1, "limited dispatch args");
}

LimitedRows LimitedDispatch::rows(uint32_t chunk, uint32_t kind) const {
  if (!cut_) return uncut();
  if (!args_ || chunk >= chunks_ || kind >= kinds_) throw Error("LimitedDispatch: no arguments recorded for this dispatch");
  return {limit_, chunk * chunkRows_, args_.get(), VkDeviceSize(chunk * kinds_ + kind) * 12};
}

void dispatchLimited(Recorder& rec, Kernel& k, std::initializer_list<BufferRange> bindings, const void* push,
                     uint32_t pushBytes, const LimitedRows& rows, uint32_t groups, const char* label) {
  std::vector<BufferRange> all(bindings);
  all.push_back(rows.limit);
  if (rows.args)
    rec.dispatchIndirect(k, all, push, pushBytes, *rows.args, rows.argsOffset, label);
  else
    rec.dispatch(k, all, push, pushBytes, groups, 1, 1, label);
}

}  // namespace vknerf::gpu

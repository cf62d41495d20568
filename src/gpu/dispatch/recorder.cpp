#include "gpu/dispatch/recorder.h"

#include <functional>
#include <string>

#include "gpu/device/device.h"
#include "gpu/compile/kernel_compiler.h"
#include "gpu/kernels/kernel_limits.h"
#include "gpu/device/vk_check.h"

namespace vknerf::gpu {

Recorder::Recorder(Context& ctx, bool timestamps, uint32_t maxTimestamps) : ctx_(ctx) {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = device(ctx).commandPool();
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(ctx.device(), &ai, &cmd_), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  check(vkCreateFence(ctx.device(), &fi, nullptr, &fence_), "vkCreateFence");
  if (timestamps && ctx.properties().limits.timestampComputeAndGraphics) {
    maxTimestamps_ = maxTimestamps;
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = 2 * maxTimestamps;
    check(vkCreateQueryPool(ctx.device(), &qi, nullptr, &queries_), "vkCreateQueryPool");
  }
}

Recorder::Recorder(Context& ctx, VkCommandBuffer external)
    : ctx_(ctx), cmd_(external), owned_(false), pending_(true) {
  if (!external) throw Error("Recorder: the caller's command buffer is VK_NULL_HANDLE");
}

Recorder::~Recorder() {
  if (!owned_) return;
  VkDevice dev = ctx_.device();
  // Nothing may be destroyed while the device still runs this command buffer.
  if (inFlight_) vkWaitForFences(dev, 1, &fence_, VK_TRUE, UINT64_MAX);
  if (queries_) vkDestroyQueryPool(dev, queries_, nullptr);
  vkDestroyFence(dev, fence_, nullptr);
  vkFreeCommandBuffers(dev, device(ctx_).commandPool(), 1, &cmd_);
}

void Recorder::begin() {
  if (!owned_) throw Error("Recorder::begin on a caller's command buffer");
  wait();  // a command buffer in flight may not be reset
  check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  check(vkBeginCommandBuffer(cmd_, &bi), "vkBeginCommandBuffer");
  labels_.clear();
  // Submission order is no memory dependency: the first command waits behind a barrier for what
  // earlier submissions (uploads, the previous step) wrote.
  pending_ = true;
  if (queries_) vkCmdResetQueryPool(cmd_, queries_, 0, 2 * maxTimestamps_);
}

// Each kernel reads what the previous one wrote; a full compute/transfer memory barrier between
// consecutive commands is the simple correct rule, and it costs nothing measurable (LAVAPIPE.md).
void Recorder::barrierIfNeeded(bool indirectNext) {
  if (!pending_) return;
  // Dispatch arguments written by a shader are read by the indirect-command stage.
  recordMemoryBarrier(cmd_, kDeviceStages, kDeviceStages | (indirectNext ? VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT : 0));
  pending_ = false;
}

VkDescriptorSet Recorder::cachedSet(Kernel& k, std::span<const BufferRange> bindings) {
  return k.descriptorSet(bindings);
}

void Recorder::recordKernel(const BoundKernel& bound, bool indirect, const std::function<void()>& issue) {
  Kernel& k = bound.kernel;
  const VkDescriptorSet set = bound.set;
  const uint32_t pushBytes = bound.pushBytes;
  const char* label = bound.label;
  if (pushBytes != k.desc().pushConstantBytes)
    throw Error(kernelName(k.desc()) + " expects " + std::to_string(k.desc().pushConstantBytes) +
                " bytes of push constants, got " + std::to_string(pushBytes));
  if (owned_) device(ctx_).compiler().dispatching(k, bound.bindings);
  barrierIfNeeded(indirect);
  bool timed = queries_ && label && labels_.size() < maxTimestamps_;
  uint32_t q = uint32_t(labels_.size()) * 2;
  if (timed) vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, q);
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline());
  vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.layout(), 0, 1, &set, 0, nullptr);
  if (pushBytes) vkCmdPushConstants(cmd_, k.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, pushBytes, bound.push);
  issue();
  if (timed) {
    vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, q + 1);
    labels_.emplace_back(labelPrefix_ + label);
  }
  pending_ = true;
}

void Recorder::dispatch(Kernel& k, std::span<const BufferRange> bindings, const void* push, uint32_t pushBytes,
                        uint32_t gx, uint32_t gy, uint32_t gz, const char* label) {
  if (gx == 0 || gy == 0 || gz == 0) return;  // empty batch: nothing to do, nothing to wait for
  checkGroupCounts(ctx_.properties().limits, k.desc().shader.name, gx, gy, gz);
  recordKernel({k, bindings, cachedSet(k, bindings), push, pushBytes, label}, false,
               [&] { vkCmdDispatch(cmd_, gx, gy, gz); });
}

void Recorder::dispatchFlat(Kernel& k, std::initializer_list<BufferRange> bindings, const void* push,
                            uint32_t pushBytes, uint64_t invocations, uint32_t local, const char* label) {
  const auto& limits = ctx_.properties().limits;
  const uint64_t groups = (invocations + local - 1) / local;
  const uint64_t maxX = limits.maxComputeWorkGroupCount[0];
  const uint64_t gy = (groups + maxX - 1) / maxX;
  const uint64_t gx = gy ? (groups + gy - 1) / gy : 0;  // as even a split as x allows
  if (gy > limits.maxComputeWorkGroupCount[1])
    throw Error(std::string(label) + ": " + std::to_string(invocations) + " invocations exceed the device's dispatch limits");
  dispatch(k, bindings, push, pushBytes, uint32_t(gx), uint32_t(gy), 1, label);
}

void Recorder::dispatchWithSet(Kernel& k, VkDescriptorSet set, const void* push, uint32_t pushBytes, uint32_t gx,
                               uint32_t gy, uint32_t gz, const char* label) {
  if (gx == 0 || gy == 0 || gz == 0) return;
  checkGroupCounts(ctx_.properties().limits, k.desc().shader.name, gx, gy, gz);
  recordKernel({k, {}, set, push, pushBytes, label}, false, [&] { vkCmdDispatch(cmd_, gx, gy, gz); });
}

void Recorder::dispatchIndirect(Kernel& k, std::span<const BufferRange> bindings, const void* push,
                                uint32_t pushBytes, const Buffer& args, VkDeviceSize offset, const char* label) {
  if (offset % 4 || offset + 12 > args.size()) throw Error("dispatchIndirect: arguments lie outside the buffer");
  recordKernel({k, bindings, cachedSet(k, bindings), push, pushBytes, label}, true,
               [&] { vkCmdDispatchIndirect(cmd_, args.handle(), offset); });
}

void Recorder::copy(const Buffer& src, Buffer& dst, VkDeviceSize bytes, VkDeviceSize srcOffset, VkDeviceSize dstOffset) {
  if (bytes == 0) return;
  barrierIfNeeded();
  VkBufferCopy region{srcOffset, dstOffset, bytes};
  vkCmdCopyBuffer(cmd_, src.handle(), dst.handle(), 1, &region);
  pending_ = true;
}

void Recorder::fill(Buffer& dst, uint32_t value, VkDeviceSize offset, VkDeviceSize bytes) {
  if (dst.size() == 0) return;
  barrierIfNeeded();
  vkCmdFillBuffer(cmd_, dst.handle(), offset, bytes == VK_WHOLE_SIZE ? VK_WHOLE_SIZE : bytes / 4 * 4, value);
  pending_ = true;
}

void Recorder::update(Buffer& dst, VkDeviceSize offset, const void* data, VkDeviceSize bytes) {
  if (bytes == 0) return;
  if (bytes % 4 || offset % 4 || bytes > 65536 || offset + bytes > dst.size())
    throw Error("Recorder::update: " + std::to_string(bytes) + " bytes at offset " + std::to_string(offset) +
                " do not fit vkCmdUpdateBuffer's rules or the buffer");
  barrierIfNeeded();
  vkCmdUpdateBuffer(cmd_, dst.handle(), offset, bytes, data);
  pending_ = true;
}

void Recorder::end() {
  if (!owned_) return;
  // The host reads what this recording wrote once its fence signals: the writes are made visible
  // to host reads here (a fence alone does not make them available on a non-coherent device).
  recordMemoryBarrier(cmd_, kDeviceStages, VK_PIPELINE_STAGE_HOST_BIT);
  check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
}

void Recorder::submitAndWait() {
  submit();
  wait();
}

void Recorder::submit() {
  if (!owned_) throw Error("Recorder::submit on a caller's command buffer");
  if (inFlight_) throw Error("Recorder::submit while its previous submission is in flight");
  device(ctx_).compiler().finish();
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd_;
  check(vkResetFences(ctx_.device(), 1, &fence_), "vkResetFences");
  submitted_ = std::chrono::steady_clock::now();
  check(vkQueueSubmit(ctx_.queue(), 1, &si, fence_), "vkQueueSubmit");
  inFlight_ = true;
}

void Recorder::wait() {
  if (!inFlight_) return;
  check(vkWaitForFences(ctx_.device(), 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  inFlight_ = false;
  device(ctx_).hostWaits()++;
  const auto waited = std::chrono::steady_clock::now();
  using Ms = std::chrono::duration<double, std::milli>;
  if (logging_) log_.push_back({Ms(submitted_ - lastWait_).count(), Ms(waited - submitted_).count(), timings()});
  lastWait_ = waited;
}

void Recorder::startLog() {
  log_.clear();
  logging_ = true;
  lastWait_ = std::chrono::steady_clock::now();
}

double Recorder::msSinceLastWait() const {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - lastWait_).count();
}

std::vector<std::pair<std::string, double>> Recorder::timings() const {
  std::vector<std::pair<std::string, double>> out;
  if (!queries_ || labels_.empty()) return out;
  std::vector<uint64_t> ts(labels_.size() * 2);
  check(vkGetQueryPoolResults(ctx_.device(), queries_, 0, uint32_t(ts.size()), ts.size() * 8, ts.data(), 8,
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  double period = ctx_.properties().limits.timestampPeriod;  // ns per tick
  for (size_t i = 0; i < labels_.size(); ++i)
    out.emplace_back(labels_[i], double(ts[2 * i + 1] - ts[2 * i]) * period * 1e-6);
  return out;
}

}  // namespace vknerf::gpu

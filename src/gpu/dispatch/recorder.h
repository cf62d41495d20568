#pragma once
// Records dispatches into one command buffer with a memory barrier between consecutive commands,
// optional timestamps per labelled dispatch, and submits once. Either owns its command buffer
// (re-submittable: a training step is recorded once and replayed) or records into a caller's.
#include <vulkan/vulkan.h>

#include <chrono>
#include <functional>
#include <initializer_list>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "vknerf/context.h"

namespace vknerf::gpu {

// One submission of an owned command buffer as the host saw it (Recorder::submissions): the host
// time before it (since the log started, or since the previous submission's wait returned), the
// time from vkQueueSubmit to its fence, and the device time of its labelled dispatches.
struct SubmissionTiming {
  double hostBeforeMs = 0, waitMs = 0;
  std::vector<std::pair<std::string, double>> kernels;
};

class Recorder {
 public:
  // Owns a command buffer and fence; `timestamps` enables per-dispatch GPU timing.
  explicit Recorder(Context& ctx, bool timestamps = false, uint32_t maxTimestamps = 256);
  // Records into the caller's command buffer (already begun); the caller submits it. The first
  // command is preceded by a full compute/transfer barrier: earlier commands of the caller's buffer,
  // or of earlier submissions to the queue, may still use the same vknerf buffers.
  Recorder(Context& ctx, VkCommandBuffer external);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  void begin();  // owned command buffer: reset and begin recording
  void dispatch(Kernel& k, std::initializer_list<BufferRange> bindings, const void* push, uint32_t pushBytes,
                uint32_t gx, uint32_t gy = 1, uint32_t gz = 1, const char* label = nullptr) {
    dispatch(k, std::span<const BufferRange>(bindings.begin(), bindings.size()), push, pushBytes, gx, gy, gz, label);
  }
  // With bindings assembled at run time.
  void dispatch(Kernel& k, std::span<const BufferRange> bindings, const void* push, uint32_t pushBytes, uint32_t gx,
                uint32_t gy, uint32_t gz, const char* label);
  template <class P>
  void dispatch(Kernel& k, std::initializer_list<BufferRange> bindings, const P& push, uint32_t gx, uint32_t gy = 1,
                uint32_t gz = 1, const char* label = nullptr) {
    dispatch(k, bindings, &push, sizeof(P), gx, gy, gz, label);
  }
  // `invocations` of a kernel of `local` invocations per workgroup that indexes them flatly
  // (sampling.glsl's flatInvocation()): groups over x, spilling into y past the device's
  // maxComputeWorkGroupCount[0], so a batch is not capped at 65,535 groups. Throws vknerf::Error when
  // even x and y together cannot hold it.
  void dispatchFlat(Kernel& k, std::initializer_list<BufferRange> bindings, const void* push, uint32_t pushBytes,
                    uint64_t invocations, uint32_t local, const char* label);
  template <class P>
  void dispatchFlat(Kernel& k, std::initializer_list<BufferRange> bindings, const P& push, uint64_t invocations,
                    uint32_t local, const char* label) {
    dispatchFlat(k, bindings, &push, sizeof(P), invocations, local, label);
  }
  // With a descriptor set the caller prepared (Kernel::transientSet: a caller's resources).
  void dispatchWithSet(Kernel& k, VkDescriptorSet set, const void* push, uint32_t pushBytes, uint32_t gx,
                       uint32_t gy = 1, uint32_t gz = 1, const char* label = nullptr);
  // Workgroup counts read on the device from a VkDispatchIndirectCommand at `offset` (e.g. written
  // by the marcher from its sample total), so a step needs no host round trip.
  void dispatchIndirect(Kernel& k, std::initializer_list<BufferRange> bindings, const void* push, uint32_t pushBytes,
                        const Buffer& args, VkDeviceSize offset, const char* label = nullptr) {
    dispatchIndirect(k, std::span<const BufferRange>(bindings.begin(), bindings.size()), push, pushBytes, args, offset,
                     label);
  }
  void dispatchIndirect(Kernel& k, std::span<const BufferRange> bindings, const void* push, uint32_t pushBytes,
                        const Buffer& args, VkDeviceSize offset, const char* label);
  void copy(const Buffer& src, Buffer& dst, VkDeviceSize bytes, VkDeviceSize srcOffset = 0, VkDeviceSize dstOffset = 0);
  void fill(Buffer& dst, uint32_t value, VkDeviceSize offset = 0, VkDeviceSize bytes = VK_WHOLE_SIZE);
  // vkCmdUpdateBuffer: `bytes` (a multiple of 4, at most 65536) copied into the command buffer now,
  // written to `dst` when it executes. Small per-recording data (a camera) without a host upload.
  void update(Buffer& dst, VkDeviceSize offset, const void* data, VkDeviceSize bytes);
  void end();
  // Owned command buffer only; may be called repeatedly after one recording. Kernels an owned
  // recording runs for the first time start compiling as they are recorded (KernelCompiler); the
  // submission first waits for them (logged as host time before it).
  void submitAndWait();
  // The two halves of submitAndWait: submit() returns at once, so that the host records the next
  // work while the device runs this; wait() (a no-op when nothing is in flight) returns once it has
  // finished and its writes are visible to the host. begin() and the destructor wait first.
  void submit();
  void wait();
  bool inFlight() const { return inFlight_; }
  // The command buffer being recorded: for a test that records what the Recorder would not (the
  // synchronization test's missing barrier).
  VkCommandBuffer commandBuffer() const { return cmd_; }

  // Milliseconds per labelled dispatch of the last submission, in recording order.
  std::vector<std::pair<std::string, double>> timings() const;

  // While one lives, the labels of the dispatches recorded get `prefix` in front, so that a profile
  // tells apart two users of the same kernels (the proposal's network from the field's). Scopes
  // nest; each restores the prefix it found.
  class LabelScope {
   public:
    LabelScope(Recorder& rec, const std::string& prefix) : rec_(rec), saved_(rec.labelPrefix_) { rec.labelPrefix_ += prefix; }
    ~LabelScope() { rec_.labelPrefix_ = saved_; }
    LabelScope(const LabelScope&) = delete;
    LabelScope& operator=(const LabelScope&) = delete;

   private:
    Recorder& rec_;
    std::string saved_;
  };

  // The submissions since startLog(), so that a whole step (several submissions and the host work
  // between them) can be attributed; kernels are timed when timestamps are enabled. Nothing is
  // logged before the first startLog(); each call clears the log.
  void startLog();
  const std::vector<SubmissionTiming>& submissions() const { return log_; }
  // Host milliseconds since the last submission's wait returned (or since startLog()).
  double msSinceLastWait() const;

 private:
  void barrierIfNeeded(bool indirectNext = false);
  // A kernel as one command binds it: the descriptor set (made from `bindings`, which are empty
  // when the caller made the set), the push constants and the timestamp label.
  struct BoundKernel {
    Kernel& kernel;
    std::span<const BufferRange> bindings;
    VkDescriptorSet set;
    const void* push;
    uint32_t pushBytes;
    const char* label;
  };
  void recordKernel(const BoundKernel& bound, bool indirect, const std::function<void()>& issue);
  static VkDescriptorSet cachedSet(Kernel& k, std::span<const BufferRange> bindings);
  Context& ctx_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  bool owned_ = true;
  bool pending_ = false;  // a command was recorded since the last barrier
  uint32_t maxTimestamps_ = 0;
  std::vector<std::string> labels_;
  std::string labelPrefix_;  // LabelScope's
  std::vector<SubmissionTiming> log_;
  bool logging_ = false;
  bool inFlight_ = false;  // submitted, not yet waited for
  std::chrono::steady_clock::time_point submitted_;
  std::chrono::steady_clock::time_point lastWait_ = std::chrono::steady_clock::now();
};

}  // namespace vknerf::gpu

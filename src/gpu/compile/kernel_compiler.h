#pragma once
// Kernels compile before they first run, in parallel on every core, with progress, and the time is
// counted (Context::compileStats), so that a command's first minute is not a silent serial compile.
//
// Lavapipe (Mesa 22.3) only translates SPIR-V to NIR at vkCreateComputePipelines; it compiles
// machine code (LLVM) when a dispatch of the pipeline executes, on the queue's one thread, once per
// variant: a storage texel buffer whose VkBuffer size is a power of two selects another variant than
// one whose size is not. It keeps each variant in Mesa's shader disk cache, keyed by the shader and
// the variant (docs/performance.md has the measurements). So when an owned command buffer records
// a dispatch of a variant not compiled yet (Recorder), a pool of threads, one per core, each with a
// private device (compile_device.h), starts compiling it at once, while recording goes on; the
// submission waits for them and for Mesa to write them (finish(), mesa_disk_cache.h), then finds
// them in the disk cache. The cache is keyed by content, so variants are remembered by content too:
// a second Kernel built from the same description is already compiled.
//
// Elsewhere nothing is compiled ahead: other drivers compile at vkCreateComputePipelines (a
// Kernel's constructor, whose time is counted here), lavapipe without its disk cache
// (MESA_SHADER_CACHE_DISABLE) would compile everything twice, and an adopted device's instance is
// the caller's, on which vknerf creates no devices.
//
// Threads: the pool's threads touch only their own CompileDevice and the queue below (under
// mutex_); everything else, and the progress callback, belongs to the thread that records and
// submits.
#include <vulkan/vulkan.h>

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <set>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/compile/compile_device.h"
#include "gpu/kernels/kernel.h"
#include "vknerf/context.h"

namespace vknerf::gpu {

// Whether kernels are compiled ahead on this device: lavapipe with its shader disk cache, and a
// device vknerf created itself.
bool kernelsCompileAhead(VkPhysicalDevice physical, bool ownDevice);

class KernelCompiler {
 public:
  // `ahead`: compile variants ahead on `threads` private devices of `physical`.
  KernelCompiler(VkPhysicalDevice physical, uint32_t queueFamily, const KernelFeatures& features, bool ahead,
                 uint32_t threads);
  ~KernelCompiler();  // waits for a compile in progress, drops the queued ones
  KernelCompiler(const KernelCompiler&) = delete;
  KernelCompiler& operator=(const KernelCompiler&) = delete;

  bool ahead() const { return ahead_; }

  // A recording dispatches `k` with `bindings`: when that variant is new, starts compiling it.
  // `bindings` may be empty for a set the caller wrote (Kernel::transientSet): then only a kernel
  // without texel bindings has a known variant. A caller's storage image never does (its size
  // selects the variant); such kernels compile at their first dispatch.
  void dispatching(const Kernel& k, std::span<const BufferRange> bindings);
  // Whether dispatching `k` with `bindings` would start a compile (a variant neither compiled nor
  // compiling).
  bool cold(const Kernel& k, std::span<const BufferRange> bindings) const;
  // Before a submission: waits until every variant started has compiled, reporting progress when
  // some were started since the last call. Throws vknerf::Error when one failed.
  void finish();

  void countPipeline(double seconds);  // a Kernel's vkCreateComputePipelines
  void setProgress(std::function<void(uint64_t done, uint64_t total)> progress);
  CompileStats stats() const;

 private:
  // The variant's key (everything the driver's cache key depends on), or "" when it has none.
  std::string key(const Kernel& k, std::span<const BufferRange> bindings, uint32_t* texelPow2) const;
  void work(CompileDevice& device);

  VkPhysicalDevice physical_;
  uint32_t queueFamily_;
  KernelFeatures features_;
  bool ahead_;
  uint32_t threads_;
  std::vector<std::unique_ptr<CompileDevice>> devices_;  // pool_[i] compiles on devices_[i]
  std::vector<std::thread> pool_;                        // started as variants come, up to threads_
  std::set<std::string> started_;  // every variant ever queued
  uint64_t startedSinceFinish_ = 0;
  std::function<void(uint64_t, uint64_t)> progress_;

  mutable std::mutex mutex_;  // guards what follows
  std::condition_variable queued_, compiled_;
  std::deque<KernelVariant> queue_;
  uint32_t busy_ = 0;  // variants being compiled
  bool stopping_ = false;
  std::exception_ptr error_;  // the first failure, rethrown by finish()
  CompileStats stats_;
};

}  // namespace vknerf::gpu

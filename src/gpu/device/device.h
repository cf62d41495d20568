#pragma once
// The Vulkan device behind a vknerf::Context: its handles, what vknerf created on it (command pool,
// pipeline cache, and for an own device the instance, debug messenger and VkDevice), and the host
// services buffers, kernels and recorders need. Internal: the public Context exposes only what an
// embedding application needs and holds this behind a pointer; vknerf's own code reaches it
// through gpu::device(ctx).
#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gpu/device/device_profile.h"
#include "vknerf/context.h"

namespace vknerf::gpu {

class KernelCompiler;

// The optional features vknerf's kernels use, as a device supports them (and as vknerf enables them).
struct KernelFeatures {
  bool shaderInt64 = false;
  bool bufferFloatAtomicAdd = false, sharedFloatAtomicAdd = false;  // VK_EXT_shader_atomic_float
  // VkPhysicalDeviceSubgroupProperties in the compute stage (Vulkan 1.1 requires only the basic
  // operations): the GL_KHR_shader_subgroup_arithmetic and _vote operations, and the subgroup size.
  bool subgroupArithmetic = false, subgroupVote = false;
  uint32_t subgroupSize = 0;
};
KernelFeatures supportedKernelFeatures(VkPhysicalDevice physical);
// `f` less what `profile` says its class lacks.
KernelFeatures profiledFeatures(KernelFeatures f, const DeviceProfile& profile);
// A VkDevice with one queue of `queueFamily` and exactly `features` enabled: vknerf's own device,
// and the private devices that compile kernels ahead (kernel_compiler.h).
VkDevice createComputeDevice(VkPhysicalDevice physical, uint32_t queueFamily, const KernelFeatures& features);

// The stages vknerf's commands run in: compute dispatches and transfers.
constexpr VkPipelineStageFlags kDeviceStages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
// A global memory barrier from the writes of `src` to the accesses of `dst` (compute, transfer,
// indirect-command reads, host reads: whichever stages `dst` names).
void recordMemoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkPipelineStageFlags dst);

class Device {
 public:
  // vknerf's own instance and device (options as for Context::create).
  static std::unique_ptr<Device> create(const ContextOptions& options);
  // The caller's handles, never destroyed here.
  static std::unique_ptr<Device> adopt(const AdoptedDevice& handles);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physical_; }
  VkDevice handle() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queueFamily_; }
  const VkPhysicalDeviceProperties& properties() const { return props_; }
  bool floatAtomics() const { return floatAtomics_; }
  bool owned() const { return ownsDevice_; }
  uint32_t validationMessages() const { return validationMessages_.load(); }
  bool validationEnabled() const { return messenger_ != VK_NULL_HANDLE; }

  // Memory type with all of `required`; -1 if none.
  int findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const;
  // The memory types with all of `required`, best first: those of the largest heap, then with fewer
  // of `avoid`'s flags. Allocation tries them in turn, so an out-of-memory heap falls back to the next.
  std::vector<uint32_t> memoryTypesFor(uint32_t typeBits, VkMemoryPropertyFlags required,
                                       VkMemoryPropertyFlags prefer = 0) const;
  const VkPhysicalDeviceMemoryProperties& memoryProperties() const { return memProps_; }
  // True when device memory is host-visible (lavapipe, integrated GPUs): buffers are mapped, no staging.
  bool unifiedMemory() const { return unified_; }
  // False where mapped memory must be flushed after host writes and invalidated before host reads
  // (a profile can force it; the flushes are then made on every device).
  bool hostCoherent() const { return hostCoherent_; }
  // New buffers are filled with NaN bytes (0xFF) before use, as a GPU's garbage would read (profiles).
  bool fillsNewBuffers() const { return profile_ != nullptr; }
  // The device profile in force (device_profile.h); nullptr: the device as it is.
  const DeviceProfile* profile() const { return profile_; }
  // Texel-buffer bindings are bound as storage buffers (the kernels' storage variants) because the
  // device's texel buffers are too small for vknerf's tables (maxTexelBufferElements).
  bool texelsAsStorage() const { return texelsAsStorage_; }
  // The most rgba32f elements one "texel" binding holds, whichever way it is bound.
  uint64_t maxTexelElements() const;
  // Live VkDeviceMemory allocations, checked against maxMemoryAllocationCount.
  std::atomic<uint32_t>& allocations() { return allocations_; }
  // Live descriptor sets in the kernels' caches (Kernel::descriptorSet): bounded, however many
  // steps a training runs (tests/unit/models/test_fast_pipeline.cpp).
  std::atomic<uint64_t>& cachedDescriptorSets() { return cachedSets_; }
  // The host's waits for the device (fences waited on: one-time submissions, recordings): how a
  // training step's stalls are counted (tests/unit/models/test_fast_pipeline.cpp).
  std::atomic<uint64_t>& hostWaits() { return hostWaits_; }
  // One-line summaries of the features, limits and memory model in force (`vknerf info`).
  std::vector<std::string> describeCapabilities() const;

  // Records `fn` into a one-time command buffer, submits it and waits. For uploads and setup only.
  void runOnce(const std::function<void(VkCommandBuffer)>& record);
  VkCommandPool commandPool() const { return pool_; }
  VkPipelineCache pipelineCache() const { return pipelineCache_; }
  // Compiles kernels before their first dispatch (kernel_compiler.h); counts compile time.
  KernelCompiler& compiler() { return *compiler_; }
  const KernelCompiler& compiler() const { return *compiler_; }
  // The features enabled on vknerf's own device (an adopted device's are the caller's: unknown).
  const KernelFeatures& features() const { return features_; }

 private:
  Device() = default;
  void initDevice(int physicalIndex);
  void initCommon();
  void requireVknerfLimits() const;
  // Context befriends Device so that this, and nothing public, can reach a Context's device.
  static Device& of(Context& ctx) { return *ctx.device_; }
  static const Device& of(const Context& ctx) { return *ctx.device_; }
  friend Device& device(Context& ctx);
  friend const Device& device(const Context& ctx);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queueFamily_ = 0;
  VkPhysicalDeviceProperties props_{};
  VkPhysicalDeviceMemoryProperties memProps_{};
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkPipelineCache pipelineCache_ = VK_NULL_HANDLE;
  KernelFeatures features_;
  std::unique_ptr<KernelCompiler> compiler_;  // its private devices go before this one
  bool ownsDevice_ = false;
  bool floatAtomics_ = false;
  bool unified_ = false;
  bool hostCoherent_ = true;
  bool texelsAsStorage_ = false;
  const DeviceProfile* profile_ = nullptr;
  std::atomic<uint32_t> allocations_{0};
  std::atomic<uint64_t> cachedSets_{0};
  std::atomic<uint64_t> hostWaits_{0};
  std::atomic<uint32_t> validationMessages_{0};  // the debug messenger's callback counts into this
};

// The one way from a Context to its internals.
inline Device& device(Context& ctx) { return Device::of(ctx); }
inline const Device& device(const Context& ctx) { return Device::of(ctx); }

}  // namespace vknerf::gpu

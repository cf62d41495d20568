#pragma once
// A private VkDevice on vknerf's physical device that makes lavapipe compile one kernel variant at
// a time (KernelCompiler runs one per core, each on its own thread). Lavapipe compiles a pipeline
// only when a dispatch of it executes, so this builds the same pipeline as the Kernel (same SPIR-V,
// layout, specialization) and records a dispatch of no workgroups: nothing runs, but the queue
// compiles the variant its bindings select and stores it in Mesa's shader disk cache, where
// vknerf's own device then finds it. The bindings are small stand-in buffers, whose sizes select
// the variant (KernelVariant::texelPow2). A device is used by one thread at a time.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "gpu/device/device.h"
#include "gpu/kernels/kernel.h"

namespace vknerf::gpu {

// A kernel as lavapipe compiles it: the pipeline and the variant its bindings select. Bit i of
// texelPow2 is set when storage texel binding i views a VkBuffer whose size is a power of two.
struct KernelVariant {
  KernelDesc desc;
  uint32_t texelPow2 = 0;
};

class CompileDevice {
 public:
  CompileDevice(VkPhysicalDevice physical, uint32_t queueFamily, const KernelFeatures& features);
  ~CompileDevice();
  CompileDevice(const CompileDevice&) = delete;
  CompileDevice& operator=(const CompileDevice&) = delete;

  // Compiles `k` (returns when the driver has); throws vknerf::Error.
  void compile(const KernelVariant& k);

 private:
  void release();
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  // The stand-ins: a storage buffer, and texel buffers of a power-of-two size and of another size.
  VkBuffer storage_ = VK_NULL_HANDLE, texelPow2_ = VK_NULL_HANDLE, texelOther_ = VK_NULL_HANDLE;
  VkBufferView viewPow2_ = VK_NULL_HANDLE, viewOther_ = VK_NULL_HANDLE;
  VkDescriptorPool descriptors_ = VK_NULL_HANDLE;
  std::vector<uint8_t> zeros_;  // push constants
};

}  // namespace vknerf::gpu

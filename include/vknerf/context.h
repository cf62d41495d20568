#pragma once
// A Vulkan compute context: either vknerf's own (headless, any Vulkan 1.2 device, lavapipe included)
// or one adopted from the embedding application, whose handles vknerf then never destroys.
#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace vknerf {

struct ContextOptions {
  // Device to use: an index into listDevices() or a case-insensitive substring of its name.
  // Empty: the VKNERF_DEVICE environment variable, else the best device
  // (discrete GPU > integrated GPU > virtual GPU > CPU).
  std::string device;
  // Enable VK_LAYER_KHRONOS_validation and count its messages. Also enabled by VKNERF_VALIDATION=1,
  // in which case a missing layer is an error (so a CI run cannot silently skip validation).
  bool validation = false;
};

// Handles owned by the embedding application. The queue must support compute.
struct AdoptedDevice {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t queueFamily = 0;
  VkQueue queue = VK_NULL_HANDLE;
  // Whether the caller enabled shaderBufferFloat32AtomicAdd (VK_EXT_shader_atomic_float).
  bool floatAtomicsEnabled = false;
};

struct DeviceInfo {
  uint32_t index = 0;
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  uint32_t apiVersion = 0;
  bool usable = false;  // Vulkan 1.2+ with a compute queue
};

class Context {
 public:
  static std::shared_ptr<Context> create(const ContextOptions& options = {});
  static std::shared_ptr<Context> adopt(const AdoptedDevice& handles);
  static std::vector<DeviceInfo> listDevices();

  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queueFamily_; }
  const VkPhysicalDeviceProperties& properties() const { return props_; }
  std::string deviceName() const { return props_.deviceName; }
  std::string describe() const;  // "llvmpipe (LLVM 15.0.6, 256 bits) [cpu, Vulkan 1.3]"
  bool isCpu() const { return props_.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }
  bool floatAtomics() const { return floatAtomics_; }
  bool owned() const { return ownsDevice_; }

  // Validation-layer warnings and errors reported since creation (own contexts with validation only).
  uint32_t validationMessages() const { return validationMessages_.load(); }
  bool validationEnabled() const { return messenger_ != VK_NULL_HANDLE; }

  // Memory type with all of `required`; -1 if none.
  int findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const;
  // True when device memory is host-visible (lavapipe, integrated GPUs): buffers are mapped, no staging.
  bool unifiedMemory() const { return unified_; }

  // Records `fn` into a one-time command buffer, submits it and waits. For uploads and setup only.
  void runOnce(const std::function<void(VkCommandBuffer)>& record);
  VkCommandPool commandPool() const { return pool_; }
  VkPipelineCache pipelineCache() const { return pipelineCache_; }

 private:
  Context() = default;
  void initDevice(int physicalIndex);
  void initCommon();

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
  bool ownsDevice_ = false;
  bool floatAtomics_ = false;
  bool unified_ = false;
  std::atomic<uint32_t> validationMessages_{0};
};

}  // namespace vknerf

#pragma once
// A Vulkan compute context: either vknerf's own (headless, any Vulkan 1.2 device, lavapipe included)
// or one adopted from the embedding application, whose handles vknerf then never destroys.
#include <vulkan/vulkan.h>

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
  // Make the device behave like another class of device (`vknerf info` lists the profiles:
  // minimum, nvidia, amd-rdna2, intel-xe-lp, mali, apple): its missing features hidden, its limits
  // and memory model in force, new buffers filled with NaN bytes. Empty: the VKNERF_DEVICE_PROFILE
  // environment variable, else the device as it is; "none": the device as it is, whatever the
  // environment says. For testing the paths other devices take.
  std::string profile;
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

// Compiling the kernels (Context::compileStats): pipelines created, and on lavapipe the kernels
// compiled ahead of their first dispatch; the wall time spent on both.
struct CompileStats {
  uint32_t pipelines = 0;      // compute pipelines created
  uint32_t compiledAhead = 0;  // kernel variants compiled before their first dispatch (lavapipe)
  double seconds = 0;
};

namespace gpu {
class Device;  // vknerf's internal Vulkan host (not installed): what Context holds
}

class Context {
 public:
  static std::shared_ptr<Context> create(const ContextOptions& options = {});
  static std::shared_ptr<Context> adopt(const AdoptedDevice& handles);
  static std::vector<DeviceInfo> listDevices();

  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const;
  VkPhysicalDevice physicalDevice() const;
  VkDevice device() const;
  VkQueue queue() const;
  uint32_t queueFamily() const;
  const VkPhysicalDeviceProperties& properties() const;
  std::string deviceName() const;
  std::string describe() const;  // "llvmpipe (LLVM 15.0.6, 256 bits) [cpu, Vulkan 1.3]"
  bool isCpu() const;
  bool floatAtomics() const;
  bool owned() const;
  // The device profile in force ("" for none) and one line each on the features, limits and memory
  // model vknerf works with and the fallbacks they select.
  std::string profile() const;
  std::vector<std::string> capabilities() const;
  static std::vector<std::string> profileNames();

  // Kernels compile before they first run. On lavapipe, which compiles a pipeline at its first
  // dispatch, the kernels a submission is about to run for the first time are compiled just before
  // it, in parallel on every core; elsewhere they compile when created. `progress`, called on the
  // submitting thread as they finish, gets (compiled so far, known so far): "compiling kernels 14/38".
  void setCompileProgress(std::function<void(uint64_t done, uint64_t total)> progress);
  CompileStats compileStats() const;

  // Validation-layer warnings and errors reported since creation (own contexts with validation only).
  uint32_t validationMessages() const;
  bool validationEnabled() const;

 private:
  // Internals stay out of the installed headers: vknerf's own code reaches them through
  // gpu::device(ctx), which goes through this friendship.
  friend class gpu::Device;
  explicit Context(std::unique_ptr<gpu::Device> device);
  std::unique_ptr<gpu::Device> device_;
};

}  // namespace vknerf

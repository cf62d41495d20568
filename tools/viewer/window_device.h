#pragma once
// The viewer's own window and Vulkan device: a GLFW window, a VkInstance with GLFW's surface
// extensions (and VK_LAYER_KHRONOS_validation under VKNERF_VALIDATION=1, its messages counted), the
// window's surface, and a device whose one queue does graphics (vkCmdBlitImage needs it), compute
// (vknerf's kernels) and present. vknerf adopts the device; this object outlives every vknerf object.
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <atomic>
#include <cstdint>
#include <string>

#include "vknerf/context.h"

namespace viewer {

struct WindowOptions {
  uint32_t width = 0, height = 0;  // client area, pixels
  std::string title = "vknerf-view";
  std::string device;              // index or name substring; empty: $VKNERF_DEVICE, else the best
};

class WindowDevice {
 public:
  // Throws vknerf::Error; without a display: "cannot open a window (is DISPLAY set?)".
  explicit WindowDevice(const WindowOptions& options);
  ~WindowDevice();
  WindowDevice(const WindowDevice&) = delete;
  WindowDevice& operator=(const WindowDevice&) = delete;

  GLFWwindow* window() const { return window_; }
  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physicalDevice() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queueFamily() const { return queueFamily_; }
  VkSurfaceKHR surface() const { return surface_; }
  std::string deviceName() const;

  // The handles for vknerf::Context::adopt.
  vknerf::AdoptedDevice adopted() const;

  bool validationEnabled() const { return messenger_ != VK_NULL_HANDLE; }
  // Validation warnings and errors so far (each also printed to stderr); still readable after
  // shutdown(), so messages from destroying the device (leaked objects) are counted too.
  uint32_t validationMessages() const { return validationMessages_.load(); }

  // Destroys the device, surface, instance and window (also done by the destructor).
  void shutdown();

 private:
  void createInstance();
  void pickDevice(const std::string& want);
  void createDevice();

  bool glfwInitialized_ = false;
  GLFWwindow* window_ = nullptr;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queueFamily_ = 0;
  bool floatAtomics_ = false;
  std::atomic<uint32_t> validationMessages_{0};
};

}  // namespace viewer

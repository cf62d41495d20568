#pragma once
// An embedding application's own Vulkan instance and device, for the tests of Context::adopt. With
// VKNERF_VALIDATION=1 it enables the validation layer (with synchronization validation) itself and
// counts the layer's messages with its own messenger: an adopted context has no messenger of
// vknerf's.
#include <vulkan/vulkan.h>

#include <cstdint>

#include "support/app_vulkan.h"

namespace vknerf::test {

struct OwnDevice {
  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice phys = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t family = 0;
  bool floatAtomics = false;
  bool validating = false;
  uint32_t& messages;  // outlives the device: vkDestroyDevice reports objects left on it

  explicit OwnDevice(uint32_t& counter);
  ~OwnDevice();  // device, messenger, instance; the layer reports any object left on the device
  OwnDevice(const OwnDevice&) = delete;
  OwnDevice& operator=(const OwnDevice&) = delete;
  AppDevice app() const { return {phys, device, queue, family}; }
};

}  // namespace vknerf::test

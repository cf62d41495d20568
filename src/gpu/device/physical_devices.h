#pragma once
// Finding a Vulkan device: the instance, the physical devices it lists, and the choice among them
// (ContextOptions::device, VKNERF_DEVICE, else the best type). Nothing here creates a VkDevice.
#include <vulkan/vulkan.h>

#include <string>
#include <vector>

#include "vknerf/context.h"

namespace vknerf::gpu {

// The instance extensions and flags vknerf asks for, given those the loader offers: debug utils
// with validation, and portability enumeration where offered, so that MoltenVK is listed.
struct InstanceRequest {
  std::vector<const char*> extensions;
  VkInstanceCreateFlags flags = 0;
};
InstanceRequest instanceRequest(const std::vector<std::string>& available, bool validation);
std::vector<std::string> availableInstanceExtensions();
// The device extensions vknerf enables, given those the device offers: the float-atomic extension
// when its add is used, and VK_KHR_portability_subset wherever the device lists it (the spec
// requires it enabled then).
std::vector<const char*> deviceExtensionsFor(const std::vector<std::string>& available, bool floatAtomics);

// A Vulkan 1.2 instance, with VK_LAYER_KHRONOS_validation and debug utils when `validation`.
// Throws vknerf::Error naming the missing driver package when there is no Vulkan driver at all.
VkInstance createInstance(bool validation);
bool layerAvailable(const char* name);

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance);
std::vector<DeviceInfo> describeDevices(VkInstance instance);
// The compute queue family vknerf uses on `pd` (a compute-only one if any); -1 if none.
int computeQueueFamily(VkPhysicalDevice pd);
// Index into `devices` of the one `want` names (index or name substring; empty: VKNERF_DEVICE, else
// the best usable type). Throws vknerf::Error listing the devices when nothing fits.
int selectDevice(const std::vector<DeviceInfo>& devices, std::string want);

// "discrete GPU", "integrated GPU", "virtual GPU", "cpu" or "other".
const char* typeName(VkPhysicalDeviceType type);

}  // namespace vknerf::gpu

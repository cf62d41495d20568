#include "support/app_device.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace vknerf::test {
namespace {

// The loader speaks through the same messenger, its messages named "Loader Message". They describe
// how the process was set up, not how the device is used: with VK_INSTANCE_LAYERS naming the
// validation layer, vkCreateInstance warns that the environment adds it, and the messenger
// chained into vkCreateInstance hears it. Shown, but not counted as validation findings.
bool fromLoader(const VkDebugUtilsMessengerCallbackDataEXT* data) {
  return data->pMessageIdName && std::strcmp(data->pMessageIdName, "Loader Message") == 0;
}

VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  if (fromLoader(data)) {
    std::fprintf(stderr, "test device: loader (not counted): %s\n", data->pMessage);
    return VK_FALSE;
  }
  std::fprintf(stderr, "test device: validation: %s\n", data->pMessage);
  ++*static_cast<uint32_t*>(user);
  return VK_FALSE;
}

}  // namespace

OwnDevice::OwnDevice(uint32_t& counter) : messages(counter) {
  validating = std::getenv("VKNERF_VALIDATION") && std::string(std::getenv("VKNERF_VALIDATION")) == "1";
  const bool validate = validating;
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.apiVersion = VK_API_VERSION_1_2;
  VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                   VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  mi.pfnUserCallback = onMessage;
  mi.pUserData = &messages;
  const char* layer = "VK_LAYER_KHRONOS_validation";
  const char* instanceExts[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME};
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  // Synchronization validation too: it checks the barriers recordRender records (between its own
  // commands, and against the application's commands before it) for read/write hazards.
  VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = &sync;
  features.pNext = &mi;  // the messenger in the chain also covers instance creation and destruction
  if (validate) {
    ci.enabledLayerCount = 1;
    ci.ppEnabledLayerNames = &layer;
    ci.enabledExtensionCount = 2;
    ci.ppEnabledExtensionNames = instanceExts;
    ci.pNext = &features;
  }
  EXPECT_EQ(vkCreateInstance(&ci, nullptr, &instance), VK_SUCCESS);
  if (validate) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
    EXPECT_NE(create, nullptr);
    if (create) EXPECT_EQ(create(instance, &mi, nullptr, &messenger), VK_SUCCESS);
  }
  uint32_t n = 1;
  vkEnumeratePhysicalDevices(instance, &n, &phys);  // the first device: any Vulkan 1.2 device works
  uint32_t nf = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(phys, &nf, nullptr);
  std::vector<VkQueueFamilyProperties> fams(nf);
  vkGetPhysicalDeviceQueueFamilyProperties(phys, &nf, fams.data());
  while (family < nf && !(fams[family].queueFlags & VK_QUEUE_COMPUTE_BIT)) ++family;
  EXPECT_LT(family, nf) << "no compute queue";

  // Float atomics when the device has them (training needs them; rendering does not).
  uint32_t ne = 0;
  vkEnumerateDeviceExtensionProperties(phys, nullptr, &ne, nullptr);
  std::vector<VkExtensionProperties> exts(ne);
  vkEnumerateDeviceExtensionProperties(phys, nullptr, &ne, exts.data());
  bool hasExt = false;
  for (auto& e : exts) hasExt |= std::strcmp(e.extensionName, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME) == 0;
  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomics{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  VkPhysicalDeviceFeatures2 supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  if (hasExt) supported.pNext = &atomics;
  vkGetPhysicalDeviceFeatures2(phys, &supported);
  floatAtomics = hasExt && atomics.shaderBufferFloat32AtomicAdd;
  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT enableAtomics{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  enableAtomics.shaderBufferFloat32AtomicAdd = floatAtomics;
  VkPhysicalDeviceFeatures2 enable{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  enable.features.shaderInt64 = supported.features.shaderInt64;
  if (floatAtomics) enable.pNext = &enableAtomics;
  const char* atomicExt = VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME;

  float priority = 1;
  VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qi.queueFamilyIndex = family;
  qi.queueCount = 1;
  qi.pQueuePriorities = &priority;
  VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  di.pNext = &enable;
  di.queueCreateInfoCount = 1;
  di.pQueueCreateInfos = &qi;
  di.enabledExtensionCount = floatAtomics ? 1 : 0;
  di.ppEnabledExtensionNames = &atomicExt;
  EXPECT_EQ(vkCreateDevice(phys, &di, nullptr, &device), VK_SUCCESS);
  vkGetDeviceQueue(device, family, 0, &queue);
}

OwnDevice::~OwnDevice() {
  if (device) vkDestroyDevice(device, nullptr);  // the layer reports any object left on it
  if (messenger) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance, messenger, nullptr);
  }
  if (instance) vkDestroyInstance(instance, nullptr);
}

}  // namespace vknerf::test

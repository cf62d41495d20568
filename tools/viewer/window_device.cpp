#include "window_device.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "vk_util.h"

namespace viewer {
namespace {

std::string lastGlfwError;
void onGlfwError(int, const char* description) { lastGlfwError = description ? description : ""; }

bool envFlag(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::strcmp(v, "0") != 0;
}

bool hasLayer(const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  return std::any_of(layers.begin(), layers.end(), [&](auto& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool hasDeviceExtension(VkPhysicalDevice pd, const char* name) {
  uint32_t n = 0;
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> exts(n);
  vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data());
  return std::any_of(exts.begin(), exts.end(), [&](auto& e) { return std::strcmp(e.extensionName, name) == 0; });
}

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  static_cast<std::atomic<uint32_t>*>(user)->fetch_add(1);
  std::fprintf(stderr, "vknerf-view: validation %s: %s\n",
               severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning",
               data->pMessage ? data->pMessage : "");
  return VK_FALSE;
}

// Same preference as vknerf's own device choice: discrete > integrated > virtual > CPU.
int typeRank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
  }
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

}  // namespace

WindowDevice::WindowDevice(const WindowOptions& o) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit()) throw vknerf::Error("cannot open a window (is DISPLAY set?)");
  glfwInitialized_ = true;
  if (!glfwVulkanSupported()) {
    shutdown();
    throw vknerf::Error("GLFW finds no Vulkan loader with surface support (install libvulkan1 and mesa-vulkan-drivers)");
  }
  try {
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    window_ = glfwCreateWindow(int(o.width), int(o.height), o.title.c_str(), nullptr, nullptr);
    if (!window_) throw vknerf::Error("cannot create a " + std::to_string(o.width) + "x" + std::to_string(o.height) + " window: " + lastGlfwError);
    createInstance();
    check(glfwCreateWindowSurface(instance_, window_, nullptr, &surface_), "glfwCreateWindowSurface");
    pickDevice(o.device);
    createDevice();
  } catch (...) {
    shutdown();
    throw;
  }
}

WindowDevice::~WindowDevice() { shutdown(); }

void WindowDevice::shutdown() {
  if (device_) vkDestroyDevice(device_, nullptr);
  if (surface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  if (window_) glfwDestroyWindow(window_);
  if (glfwInitialized_) glfwTerminate();
  glfwInitialized_ = false;
  device_ = VK_NULL_HANDLE;
  surface_ = VK_NULL_HANDLE;
  messenger_ = VK_NULL_HANDLE;
  instance_ = VK_NULL_HANDLE;
  window_ = nullptr;
}

void WindowDevice::createInstance() {
  // Validation is forced by VKNERF_VALIDATION=1 exactly as for vknerf's own contexts: a missing layer
  // is then an error, so a CI run cannot silently go unvalidated.
  const bool validation = envFlag("VKNERF_VALIDATION");
  if (validation && !hasLayer("VK_LAYER_KHRONOS_validation"))
    throw vknerf::Error("VKNERF_VALIDATION=1 but VK_LAYER_KHRONOS_validation is not installed (vulkan-validationlayers)");

  uint32_t glfwCount = 0;
  const char** glfwExts = glfwGetRequiredInstanceExtensions(&glfwCount);
  if (!glfwExts) throw vknerf::Error("GLFW reports no Vulkan surface extensions for this display: " + lastGlfwError);
  std::vector<const char*> exts(glfwExts, glfwExts + glfwCount);
  std::vector<const char*> layers;
  if (validation) {
    layers.push_back("VK_LAYER_KHRONOS_validation");
    exts.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "vknerf-view";
  app.apiVersion = VK_API_VERSION_1_2;
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  ci.enabledLayerCount = uint32_t(layers.size());
  ci.ppEnabledLayerNames = layers.data();
  ci.enabledExtensionCount = uint32_t(exts.size());
  ci.ppEnabledExtensionNames = exts.data();
  check(vkCreateInstance(&ci, nullptr, &instance_), "vkCreateInstance");

  if (validation) {
    VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    mi.pfnUserCallback = onValidationMessage;
    mi.pUserData = &validationMessages_;
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (!create) throw vknerf::Error("VK_EXT_debug_utils: vkCreateDebugUtilsMessengerEXT not found");
    check(create(instance_, &mi, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
  }
}

void WindowDevice::pickDevice(const std::string& option) {
  std::string want = option;
  if (want.empty())
    if (const char* env = std::getenv("VKNERF_DEVICE")) want = env;
  const bool numeric = !want.empty() && std::all_of(want.begin(), want.end(), [](unsigned char c) { return std::isdigit(c); });

  uint32_t n = 0;
  vkEnumeratePhysicalDevices(instance_, &n, nullptr);
  std::vector<VkPhysicalDevice> devices(n);
  if (n) vkEnumeratePhysicalDevices(instance_, &n, devices.data());
  int bestRank = -1;
  std::string names;
  for (uint32_t i = 0; i < n; ++i) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(devices[i], &p);
    names += (names.empty() ? "" : ", ") + std::to_string(i) + ": " + p.deviceName;
    if (!want.empty() && (numeric ? std::to_string(i) != want : lower(p.deviceName).find(lower(want)) == std::string::npos))
      continue;
    if (p.apiVersion < VK_API_VERSION_1_2 || !hasDeviceExtension(devices[i], VK_KHR_SWAPCHAIN_EXTENSION_NAME)) continue;
    // One queue does everything: compute for vknerf, graphics for the blit, and present.
    uint32_t nf = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(devices[i], &nf, nullptr);
    std::vector<VkQueueFamilyProperties> fams(nf);
    vkGetPhysicalDeviceQueueFamilyProperties(devices[i], &nf, fams.data());
    for (uint32_t f = 0; f < nf; ++f) {
      const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
      VkBool32 present = VK_FALSE;
      vkGetPhysicalDeviceSurfaceSupportKHR(devices[i], f, surface_, &present);
      if ((fams[f].queueFlags & need) != need || !present) continue;
      if (typeRank(p.deviceType) > bestRank) {
        bestRank = typeRank(p.deviceType);
        physical_ = devices[i];
        queueFamily_ = f;
      }
      break;
    }
  }
  if (!physical_)
    throw vknerf::Error("no Vulkan 1.2 device " + (want.empty() ? std::string() : "matching '" + want + "' ") +
                        "with a queue for graphics, compute and presenting to the window (devices: " + names + ")");
}

void WindowDevice::createDevice() {
  // The features vknerf's kernels use: float atomic adds (the MLP's gradient reductions) and int64.
  const bool hasAtomicExt = hasDeviceExtension(physical_, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomics{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  VkPhysicalDeviceFeatures2 supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  if (hasAtomicExt) supported.pNext = &atomics;
  vkGetPhysicalDeviceFeatures2(physical_, &supported);
  floatAtomics_ = hasAtomicExt && atomics.shaderBufferFloat32AtomicAdd;

  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT enableAtomics{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  enableAtomics.shaderBufferFloat32AtomicAdd = atomics.shaderBufferFloat32AtomicAdd;
  enableAtomics.shaderSharedFloat32AtomicAdd = atomics.shaderSharedFloat32AtomicAdd;
  VkPhysicalDeviceFeatures2 enable{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  enable.features.shaderInt64 = supported.features.shaderInt64;
  if (floatAtomics_) enable.pNext = &enableAtomics;
  std::vector<const char*> exts{VK_KHR_SWAPCHAIN_EXTENSION_NAME};
  if (floatAtomics_) exts.push_back(VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);

  float priority = 1.0f;
  VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qi.queueFamilyIndex = queueFamily_;
  qi.queueCount = 1;
  qi.pQueuePriorities = &priority;
  VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  di.pNext = &enable;
  di.queueCreateInfoCount = 1;
  di.pQueueCreateInfos = &qi;
  di.enabledExtensionCount = uint32_t(exts.size());
  di.ppEnabledExtensionNames = exts.data();
  check(vkCreateDevice(physical_, &di, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
}

std::string WindowDevice::deviceName() const {
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(physical_, &p);
  return p.deviceName;
}

vknerf::AdoptedDevice WindowDevice::adopted() const {
  return {instance_, physical_, device_, queueFamily_, queue_, floatAtomics_};
}

}  // namespace viewer

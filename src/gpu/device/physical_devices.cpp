#include "gpu/device/physical_devices.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>

#include "gpu/device/vk_check.h"

namespace vknerf::gpu {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

int typeRank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
  }
}

}  // namespace

const char* typeName(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
}

int computeQueueFamily(VkPhysicalDevice pd) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> fams(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, fams.data());
  // Prefer a compute-only family (async compute on GPUs), else any family with compute.
  for (uint32_t i = 0; i < n; ++i)
    if ((fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT) && !(fams[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)) return int(i);
  for (uint32_t i = 0; i < n; ++i)
    if (fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT) return int(i);
  return -1;
}

bool layerAvailable(const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  for (auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

std::vector<std::string> availableInstanceExtensions() {
  uint32_t n = 0;
  vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> props(n);
  vkEnumerateInstanceExtensionProperties(nullptr, &n, props.data());
  std::vector<std::string> names;
  for (const auto& p : props) names.emplace_back(p.extensionName);
  return names;
}

InstanceRequest instanceRequest(const std::vector<std::string>& available, bool validation) {
  auto has = [&](const char* name) { return std::find(available.begin(), available.end(), name) != available.end(); };
  InstanceRequest r;
  if (validation) r.extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  // A loader from 1.3.216 on lists portability drivers (MoltenVK) only to an instance that asks
  // for them; vknerf keeps to what the portability subset allows (gpu::createComputeDevice).
  if (has(VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME)) {
    r.extensions.push_back(VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME);
    r.flags |= VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR;
  }
  return r;
}

std::vector<const char*> deviceExtensionsFor(const std::vector<std::string>& available, bool floatAtomics) {
  auto has = [&](const char* name) { return std::find(available.begin(), available.end(), name) != available.end(); };
  std::vector<const char*> exts;
  if (floatAtomics) exts.push_back(VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
  // A device that lists VK_KHR_portability_subset must have it enabled (VUID-VkDeviceCreateInfo-pProperties-04451).
  if (has("VK_KHR_portability_subset")) exts.push_back("VK_KHR_portability_subset");
  return exts;
}

VkInstance createInstance(bool validation) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "vknerf";
  app.pEngineName = "vknerf";
  app.apiVersion = VK_API_VERSION_1_2;
  std::vector<const char*> layers;
  if (validation) layers.push_back("VK_LAYER_KHRONOS_validation");
  const InstanceRequest request = instanceRequest(availableInstanceExtensions(), validation);
  const std::vector<const char*>& exts = request.extensions;
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.flags = request.flags;
  ci.pApplicationInfo = &app;
  ci.enabledLayerCount = uint32_t(layers.size());
  ci.ppEnabledLayerNames = layers.data();
  ci.enabledExtensionCount = uint32_t(exts.size());
  ci.ppEnabledExtensionNames = exts.data();
  VkInstance inst = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&ci, nullptr, &inst);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
    throw Error("no Vulkan driver found (vkCreateInstance: " + std::string(resultName(r)) +
                "); install mesa-vulkan-drivers for the CPU device (lavapipe)");
  check(r, "vkCreateInstance");
  return inst;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance inst) {
  uint32_t n = 0;
  vkEnumeratePhysicalDevices(inst, &n, nullptr);
  std::vector<VkPhysicalDevice> pds(n);
  if (n) vkEnumeratePhysicalDevices(inst, &n, pds.data());
  return pds;
}

std::vector<DeviceInfo> describeDevices(VkInstance inst) {
  std::vector<DeviceInfo> out;
  auto pds = physicalDevices(inst);
  for (uint32_t i = 0; i < pds.size(); ++i) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(pds[i], &p);
    out.push_back({i, p.deviceName, p.deviceType, p.apiVersion,
                   p.apiVersion >= VK_API_VERSION_1_2 && computeQueueFamily(pds[i]) >= 0});
  }
  return out;
}

int selectDevice(const std::vector<DeviceInfo>& devices, std::string want) {
  if (devices.empty()) throw Error("no Vulkan device found; install mesa-vulkan-drivers for the CPU device (lavapipe)");
  if (want.empty())
    if (const char* env = std::getenv("VKNERF_DEVICE")) want = env;
  std::string names;
  for (auto& d : devices) names += (names.empty() ? "" : ", ") + std::to_string(d.index) + ": " + d.name;
  if (!want.empty()) {
    bool numeric = std::all_of(want.begin(), want.end(), [](unsigned char c) { return std::isdigit(c); });
    for (auto& d : devices) {
      bool match = numeric ? std::to_string(d.index) == want : lower(d.name).find(lower(want)) != std::string::npos;
      if (!match) continue;
      if (!d.usable) throw Error("device '" + d.name + "' lacks Vulkan 1.2 or a compute queue");
      return int(d.index);
    }
    throw Error("no Vulkan device matches '" + want + "' (devices: " + names + ")");
  }
  int best = -1;
  for (auto& d : devices)
    if (d.usable && (best < 0 || typeRank(d.type) > typeRank(devices[best].type))) best = int(d.index);
  if (best < 0) throw Error("no Vulkan 1.2 device with a compute queue (devices: " + names + ")");
  return best;
}

}  // namespace vknerf::gpu

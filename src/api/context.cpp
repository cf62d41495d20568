#include "vknerf/context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "gpu/vk_check.h"

namespace vknerf {
namespace gpu {

const char* resultName(VkResult r) {
  switch (r) {
#define CASE(x) case x: return #x;
    CASE(VK_NOT_READY) CASE(VK_TIMEOUT) CASE(VK_INCOMPLETE)
    CASE(VK_ERROR_OUT_OF_HOST_MEMORY) CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    CASE(VK_ERROR_INITIALIZATION_FAILED) CASE(VK_ERROR_DEVICE_LOST) CASE(VK_ERROR_MEMORY_MAP_FAILED)
    CASE(VK_ERROR_LAYER_NOT_PRESENT) CASE(VK_ERROR_EXTENSION_NOT_PRESENT) CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    CASE(VK_ERROR_INCOMPATIBLE_DRIVER) CASE(VK_ERROR_TOO_MANY_OBJECTS) CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    CASE(VK_ERROR_FRAGMENTED_POOL) CASE(VK_ERROR_OUT_OF_POOL_MEMORY) CASE(VK_ERROR_UNKNOWN)
#undef CASE
    default: return "VkResult error";
  }
}

}  // namespace gpu

namespace {

using gpu::check;

bool envFlag(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::strcmp(v, "0") != 0;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

const char* typeName(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
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

VKAPI_ATTR VkBool32 VKAPI_CALL onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                              VkDebugUtilsMessageTypeFlagsEXT,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    static_cast<std::atomic<uint32_t>*>(user)->fetch_add(1);
    std::fprintf(stderr, "vknerf: validation %s: %s\n",
                 severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning",
                 data->pMessage ? data->pMessage : "");
  }
  return VK_FALSE;
}

VkInstance createInstance(bool validation) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "vknerf";
  app.pEngineName = "vknerf";
  app.apiVersion = VK_API_VERSION_1_2;
  std::vector<const char*> layers, exts;
  if (validation) {
    layers.push_back("VK_LAYER_KHRONOS_validation");
    exts.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  ci.enabledLayerCount = uint32_t(layers.size());
  ci.ppEnabledLayerNames = layers.data();
  ci.enabledExtensionCount = uint32_t(exts.size());
  ci.ppEnabledExtensionNames = exts.data();
  VkInstance inst = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&ci, nullptr, &inst);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
    throw Error("no Vulkan driver found (vkCreateInstance: " + std::string(gpu::resultName(r)) +
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

}  // namespace

std::vector<DeviceInfo> Context::listDevices() {
  VkInstance inst = createInstance(false);
  auto out = describeDevices(inst);
  vkDestroyInstance(inst, nullptr);
  return out;
}

std::shared_ptr<Context> Context::create(const ContextOptions& options) {
  std::shared_ptr<Context> ctx(new Context());
  bool forced = envFlag("VKNERF_VALIDATION");
  bool validation = options.validation || forced;
  if (validation && !layerAvailable("VK_LAYER_KHRONOS_validation")) {
    if (forced) throw Error("VKNERF_VALIDATION=1 but VK_LAYER_KHRONOS_validation is not installed (vulkan-validationlayers)");
    validation = false;
  }
  ctx->ownsDevice_ = true;
  ctx->instance_ = createInstance(validation);
  if (validation) {
    VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
    mi.pfnUserCallback = onDebugMessage;
    mi.pUserData = &ctx->validationMessages_;
    auto fn = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(ctx->instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (fn) check(fn(ctx->instance_, &mi, nullptr, &ctx->messenger_), "vkCreateDebugUtilsMessengerEXT");
  }
  ctx->initDevice(selectDevice(describeDevices(ctx->instance_), options.device));
  return ctx;
}

void Context::initDevice(int physicalIndex) {
  physical_ = physicalDevices(instance_)[physicalIndex];
  queueFamily_ = uint32_t(computeQueueFamily(physical_));

  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomicFloat{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  uint32_t extCount = 0;
  vkEnumerateDeviceExtensionProperties(physical_, nullptr, &extCount, nullptr);
  std::vector<VkExtensionProperties> exts(extCount);
  vkEnumerateDeviceExtensionProperties(physical_, nullptr, &extCount, exts.data());
  bool hasAtomicFloat = std::any_of(exts.begin(), exts.end(), [](auto& e) {
    return std::strcmp(e.extensionName, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME) == 0;
  });
  VkPhysicalDeviceFeatures2 supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  if (hasAtomicFloat) supported.pNext = &atomicFloat;
  vkGetPhysicalDeviceFeatures2(physical_, &supported);
  floatAtomics_ = hasAtomicFloat && atomicFloat.shaderBufferFloat32AtomicAdd;

  // Enable only what the kernels use.
  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT enableAtomic{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  enableAtomic.shaderBufferFloat32AtomicAdd = atomicFloat.shaderBufferFloat32AtomicAdd;
  enableAtomic.shaderSharedFloat32AtomicAdd = atomicFloat.shaderSharedFloat32AtomicAdd;
  VkPhysicalDeviceFeatures2 enable{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  enable.features.shaderInt64 = supported.features.shaderInt64;
  if (floatAtomics_) enable.pNext = &enableAtomic;
  std::vector<const char*> deviceExts;
  if (floatAtomics_) deviceExts.push_back(VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);

  float priority = 1.0f;
  VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qi.queueFamilyIndex = queueFamily_;
  qi.queueCount = 1;
  qi.pQueuePriorities = &priority;
  VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  di.pNext = &enable;
  di.queueCreateInfoCount = 1;
  di.pQueueCreateInfos = &qi;
  di.enabledExtensionCount = uint32_t(deviceExts.size());
  di.ppEnabledExtensionNames = deviceExts.data();
  check(vkCreateDevice(physical_, &di, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
  initCommon();
}

std::shared_ptr<Context> Context::adopt(const AdoptedDevice& h) {
  if (!h.instance || !h.physicalDevice || !h.device || !h.queue)
    throw Error("Context::adopt: instance, physicalDevice, device and queue must all be set");
  std::shared_ptr<Context> ctx(new Context());
  ctx->ownsDevice_ = false;
  ctx->instance_ = h.instance;
  ctx->physical_ = h.physicalDevice;
  ctx->device_ = h.device;
  ctx->queue_ = h.queue;
  ctx->queueFamily_ = h.queueFamily;
  ctx->floatAtomics_ = h.floatAtomicsEnabled;
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(h.physicalDevice, &n, nullptr);
  std::vector<VkQueueFamilyProperties> fams(n);
  vkGetPhysicalDeviceQueueFamilyProperties(h.physicalDevice, &n, fams.data());
  if (h.queueFamily >= n || !(fams[h.queueFamily].queueFlags & VK_QUEUE_COMPUTE_BIT))
    throw Error("Context::adopt: queue family " + std::to_string(h.queueFamily) + " has no compute support");
  ctx->initCommon();
  return ctx;
}

void Context::initCommon() {
  vkGetPhysicalDeviceProperties(physical_, &props_);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memProps_);
  if (props_.apiVersion < VK_API_VERSION_1_2) throw Error(std::string(props_.deviceName) + " supports only Vulkan < 1.2");
  // Unified memory: every buffer can live in device-local, host-visible, coherent memory and be
  // mapped once. True on lavapipe (one memory type) and integrated GPUs; discrete GPUs use staging.
  const auto unifiedFlags = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  unified_ = props_.deviceType != VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU && findMemoryType(~0u, unifiedFlags) >= 0;

  VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pi.queueFamilyIndex = queueFamily_;
  check(vkCreateCommandPool(device_, &pi, nullptr, &pool_), "vkCreateCommandPool");
  VkPipelineCacheCreateInfo ci{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
  check(vkCreatePipelineCache(device_, &ci, nullptr, &pipelineCache_), "vkCreatePipelineCache");
}

Context::~Context() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (pipelineCache_) vkDestroyPipelineCache(device_, pipelineCache_, nullptr);
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
  }
  if (!ownsDevice_) return;
  if (device_) vkDestroyDevice(device_, nullptr);
  if (messenger_) {
    auto fn = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (fn) fn(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

std::string Context::describe() const {
  std::ostringstream os;
  os << props_.deviceName << " [" << typeName(props_.deviceType) << ", Vulkan " << VK_API_VERSION_MAJOR(props_.apiVersion)
     << "." << VK_API_VERSION_MINOR(props_.apiVersion) << (floatAtomics_ ? ", float atomics" : "") << "]";
  return os.str();
}

int Context::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const {
  for (uint32_t i = 0; i < memProps_.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (memProps_.memoryTypes[i].propertyFlags & required) == required) return int(i);
  return -1;
}

void Context::runOnce(const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd;
  check(vkAllocateCommandBuffers(device_, &ai, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vkBeginCommandBuffer(cmd, &bi);
  record(cmd);
  vkEndCommandBuffer(cmd);
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence;
  check(vkCreateFence(device_, &fi, nullptr, &fence), "vkCreateFence");
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  VkResult r = vkQueueSubmit(queue_, 1, &si, fence);
  if (r == VK_SUCCESS) r = vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX);
  vkDestroyFence(device_, fence, nullptr);
  vkFreeCommandBuffers(device_, pool_, 1, &cmd);
  check(r, "vkQueueSubmit/vkWaitForFences");
}

}  // namespace vknerf

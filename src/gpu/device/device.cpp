#include "gpu/device/device.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "gpu/compile/kernel_compiler.h"
#include "gpu/device/physical_devices.h"
#include "gpu/device/vk_check.h"

namespace vknerf::gpu {
namespace {

bool envFlag(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::strcmp(v, "0") != 0;
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

}  // namespace

void recordMemoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkPipelineStageFlags dst) {
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = 0;
  if (dst & VK_PIPELINE_STAGE_HOST_BIT) mb.dstAccessMask |= VK_ACCESS_HOST_READ_BIT;
  if (dst & (VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT))
    mb.dstAccessMask |= VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                        VK_ACCESS_TRANSFER_WRITE_BIT;
  if (dst & VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT) mb.dstAccessMask |= VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
  vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

// Built inside a unique_ptr from the start: if a later step throws, the destructor releases what
// the earlier ones created.
std::unique_ptr<Device> Device::create(const ContextOptions& options) {
  std::unique_ptr<Device> d(new Device());
  bool forced = envFlag("VKNERF_VALIDATION");
  bool validation = options.validation || forced;
  if (validation && !layerAvailable("VK_LAYER_KHRONOS_validation")) {
    if (forced) throw Error("VKNERF_VALIDATION=1 but VK_LAYER_KHRONOS_validation is not installed (vulkan-validationlayers)");
    validation = false;
  }
  d->ownsDevice_ = true;
  if (std::string name = requestedProfile(options.profile); !name.empty()) d->profile_ = &deviceProfile(name);
  d->instance_ = createInstance(validation);
  if (validation) {
    VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT;
    mi.pfnUserCallback = onDebugMessage;
    mi.pUserData = &d->validationMessages_;
    auto fn = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(d->instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (fn) check(fn(d->instance_, &mi, nullptr, &d->messenger_), "vkCreateDebugUtilsMessengerEXT");
  }
  d->initDevice(selectDevice(describeDevices(d->instance_), options.device));
  return d;
}

KernelFeatures supportedKernelFeatures(VkPhysicalDevice physical) {
  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomicFloat{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  uint32_t extCount = 0;
  vkEnumerateDeviceExtensionProperties(physical, nullptr, &extCount, nullptr);
  std::vector<VkExtensionProperties> exts(extCount);
  vkEnumerateDeviceExtensionProperties(physical, nullptr, &extCount, exts.data());
  bool hasAtomicFloat = std::any_of(exts.begin(), exts.end(), [](auto& e) {
    return std::strcmp(e.extensionName, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME) == 0;
  });
  VkPhysicalDeviceFeatures2 supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  if (hasAtomicFloat) supported.pNext = &atomicFloat;
  vkGetPhysicalDeviceFeatures2(physical, &supported);
  KernelFeatures f;
  f.shaderInt64 = supported.features.shaderInt64;
  f.bufferFloatAtomicAdd = hasAtomicFloat && atomicFloat.shaderBufferFloat32AtomicAdd;
  f.sharedFloatAtomicAdd = f.bufferFloatAtomicAdd && atomicFloat.shaderSharedFloat32AtomicAdd;
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props.pNext = &subgroup;
  vkGetPhysicalDeviceProperties2(physical, &props);
  const bool compute = subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT;
  f.subgroupArithmetic = compute && (subgroup.supportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT);
  f.subgroupVote = compute && (subgroup.supportedOperations & VK_SUBGROUP_FEATURE_VOTE_BIT);
  f.subgroupSize = subgroup.subgroupSize;
  return f;
}

KernelFeatures profiledFeatures(KernelFeatures f, const DeviceProfile& p) {
  f.shaderInt64 = f.shaderInt64 && p.int64;
  f.bufferFloatAtomicAdd = f.bufferFloatAtomicAdd && p.floatAtomicAdd;
  f.sharedFloatAtomicAdd = f.sharedFloatAtomicAdd && p.floatAtomicAdd;
  f.subgroupArithmetic = f.subgroupArithmetic && p.subgroupArithmetic;
  f.subgroupVote = f.subgroupVote && p.subgroupVote;
  // The kernels are compiled for the real device, whose subgroups stay as they are: a profile's
  // size only describes its class.
  return f;
}

VkDevice createComputeDevice(VkPhysicalDevice physical, uint32_t queueFamily, const KernelFeatures& f) {
  // Enable only what the kernels use.
  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT enableAtomic{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  enableAtomic.shaderBufferFloat32AtomicAdd = f.bufferFloatAtomicAdd;
  enableAtomic.shaderSharedFloat32AtomicAdd = f.sharedFloatAtomicAdd;
  VkPhysicalDeviceFeatures2 enable{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  enable.features.shaderInt64 = f.shaderInt64;
  if (f.bufferFloatAtomicAdd) enable.pNext = &enableAtomic;
  uint32_t extCount = 0;
  vkEnumerateDeviceExtensionProperties(physical, nullptr, &extCount, nullptr);
  std::vector<VkExtensionProperties> props(extCount);
  vkEnumerateDeviceExtensionProperties(physical, nullptr, &extCount, props.data());
  std::vector<std::string> available;
  for (const auto& e : props) available.emplace_back(e.extensionName);
  const std::vector<const char*> deviceExts = deviceExtensionsFor(available, f.bufferFloatAtomicAdd);

  float priority = 1.0f;
  VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qi.queueFamilyIndex = queueFamily;
  qi.queueCount = 1;
  qi.pQueuePriorities = &priority;
  VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  di.pNext = &enable;
  di.queueCreateInfoCount = 1;
  di.pQueueCreateInfos = &qi;
  di.enabledExtensionCount = uint32_t(deviceExts.size());
  di.ppEnabledExtensionNames = deviceExts.data();
  VkDevice device = VK_NULL_HANDLE;
  check(vkCreateDevice(physical, &di, nullptr, &device), "vkCreateDevice");
  return device;
}

void Device::initDevice(int physicalIndex) {
  physical_ = physicalDevices(instance_)[physicalIndex];
  queueFamily_ = uint32_t(computeQueueFamily(physical_));
  features_ = supportedKernelFeatures(physical_);
  if (profile_) features_ = profiledFeatures(features_, *profile_);
  floatAtomics_ = features_.bufferFloatAtomicAdd;
  device_ = createComputeDevice(physical_, queueFamily_, features_);
  vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
  initCommon();
}

std::unique_ptr<Device> Device::adopt(const AdoptedDevice& h) {
  if (!h.instance || !h.physicalDevice || !h.device || !h.queue)
    throw Error("Context::adopt: instance, physicalDevice, device and queue must all be set");
  std::unique_ptr<Device> d(new Device());
  d->ownsDevice_ = false;
  d->instance_ = h.instance;
  d->physical_ = h.physicalDevice;
  d->device_ = h.device;
  d->queue_ = h.queue;
  d->queueFamily_ = h.queueFamily;
  if (std::string name = requestedProfile(""); !name.empty()) d->profile_ = &deviceProfile(name);
  // Subgroup operations need no enabling; float atomics and int64 are what the caller enabled.
  d->features_ = supportedKernelFeatures(h.physicalDevice);
  d->features_.bufferFloatAtomicAdd = h.floatAtomicsEnabled;
  d->features_.sharedFloatAtomicAdd = false;
  d->features_.shaderInt64 = false;
  if (d->profile_) d->features_ = profiledFeatures(d->features_, *d->profile_);
  d->floatAtomics_ = d->features_.bufferFloatAtomicAdd;
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(h.physicalDevice, &n, nullptr);
  std::vector<VkQueueFamilyProperties> fams(n);
  vkGetPhysicalDeviceQueueFamilyProperties(h.physicalDevice, &n, fams.data());
  if (h.queueFamily >= n || !(fams[h.queueFamily].queueFlags & VK_QUEUE_COMPUTE_BIT))
    throw Error("Context::adopt: queue family " + std::to_string(h.queueFamily) + " has no compute support");
  d->initCommon();
  return d;
}

void Device::initCommon() {
  vkGetPhysicalDeviceProperties(physical_, &props_);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memProps_);
  if (props_.apiVersion < VK_API_VERSION_1_2) throw Error(std::string(props_.deviceName) + " supports only Vulkan < 1.2");
  if (profile_) applyProfileLimits(*profile_, props_.limits);
  requireVknerfLimits();
  // Unified memory: every buffer can live in device-local, host-visible memory and be mapped once.
  // True on lavapipe (one memory type) and integrated GPUs; discrete GPUs use staging. A profile
  // forces its class's model, and may make mapped memory non-coherent.
  const auto unifiedFlags = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
  const bool canMap = findMemoryType(~0u, unifiedFlags) >= 0;
  unified_ = profile_ ? canMap && profile_->memory == MemoryModel::Unified
                      : props_.deviceType != VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU && canMap;
  hostCoherent_ = !profile_ || profile_->hostCoherent;
  // Texel buffers hold vknerf's largest tables (hash grid, Adam over them) only from 2^24 elements
  // on (256 MiB of rgba32f); below that the kernels bind them as storage buffers instead.
  texelsAsStorage_ = props_.limits.maxTexelBufferElements < (1u << 24);

  VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pi.queueFamilyIndex = queueFamily_;
  check(vkCreateCommandPool(device_, &pi, nullptr, &pool_), "vkCreateCommandPool");
  VkPipelineCacheCreateInfo ci{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
  check(vkCreatePipelineCache(device_, &ci, nullptr, &pipelineCache_), "vkCreatePipelineCache");
  compiler_ = std::make_unique<KernelCompiler>(physical_, queueFamily_, features_,
                                               kernelsCompileAhead(physical_, ownsDevice_),
                                               std::thread::hardware_concurrency());
}

Device::~Device() {
  compiler_.reset();  // its devices are children of this instance
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (pipelineCache_) vkDestroyPipelineCache(device_, pipelineCache_, nullptr);
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
  }
  if (!ownsDevice_) return;  // an adopted device: the caller's handles stay alive
  if (device_) vkDestroyDevice(device_, nullptr);
  if (messenger_) {
    auto fn = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (fn) fn(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

void Device::requireVknerfLimits() const {
  const auto& l = props_.limits;
  auto need = [&](const char* what, uint64_t has, uint64_t needs) {
    if (has < needs)
      throw Error(std::string(props_.deviceName) + ": " + what + " is " + std::to_string(has) + ", vknerf's kernels need " +
                  std::to_string(needs));
  };
  need("maxComputeWorkGroupInvocations", l.maxComputeWorkGroupInvocations, 256);
  need("maxComputeWorkGroupSize[0]", l.maxComputeWorkGroupSize[0], 256);
  need("maxPerStageDescriptorStorageBuffers", l.maxPerStageDescriptorStorageBuffers, 16);
  need("maxPushConstantsSize", l.maxPushConstantsSize, 128);
}

uint64_t Device::maxTexelElements() const {
  return texelsAsStorage_ ? props_.limits.maxStorageBufferRange / 16 : props_.limits.maxTexelBufferElements;
}

std::vector<uint32_t> Device::memoryTypesFor(uint32_t typeBits, VkMemoryPropertyFlags required,
                                             VkMemoryPropertyFlags prefer) const {
  std::vector<uint32_t> types;
  for (uint32_t i = 0; i < memProps_.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (memProps_.memoryTypes[i].propertyFlags & required) == required) types.push_back(i);
  auto preferred = [&](uint32_t t) { return (memProps_.memoryTypes[t].propertyFlags & prefer) == prefer; };
  auto heapSize = [&](uint32_t t) { return memProps_.memoryHeaps[memProps_.memoryTypes[t].heapIndex].size; };
  std::stable_sort(types.begin(), types.end(), [&](uint32_t a, uint32_t b) {
    if (preferred(a) != preferred(b)) return preferred(a);
    return heapSize(a) > heapSize(b);
  });
  return types;
}

std::vector<std::string> Device::describeCapabilities() const {
  const auto& l = props_.limits;
  const auto& f = features_;
  auto yes = [](bool b) { return b ? "yes" : "no"; };
  std::vector<std::string> out;
  out.push_back("profile: " + std::string(profile_ ? std::string(profile_->name) + " (" + profile_->source + ")"
                                                   : std::string("none (the device as it is)")));
  out.push_back(std::string("features: buffer float atomic add ") + yes(f.bufferFloatAtomicAdd) + ", subgroup arithmetic " +
                yes(f.subgroupArithmetic) + ", subgroup vote " + yes(f.subgroupVote) + ", int64 " + yes(f.shaderInt64) +
                ", subgroup size " + std::to_string(f.subgroupSize));
  out.push_back("limits: workgroups " + std::to_string(l.maxComputeWorkGroupCount[0]) + " x " +
                std::to_string(l.maxComputeWorkGroupCount[1]) + " x " + std::to_string(l.maxComputeWorkGroupCount[2]) +
                ", " + std::to_string(l.maxComputeWorkGroupInvocations) + " invocations, shared memory " +
                std::to_string(l.maxComputeSharedMemorySize) + " B, storage range " + std::to_string(l.maxStorageBufferRange) +
                " B, texel buffer " + std::to_string(l.maxTexelBufferElements) + " elements, push constants " +
                std::to_string(l.maxPushConstantsSize) + " B, " + std::to_string(l.maxPerStageDescriptorStorageBuffers) +
                " storage buffers per stage, " + std::to_string(l.maxMemoryAllocationCount) + " allocations");
  out.push_back("alignments: storage offset " + std::to_string(l.minStorageBufferOffsetAlignment) + ", texel offset " +
                std::to_string(l.minTexelBufferOffsetAlignment) + ", non-coherent atom " + std::to_string(l.nonCoherentAtomSize));
  out.push_back(std::string("memory: ") + (unified_ ? "unified (device buffers mapped by the host)"
                                                    : "discrete (device-local buffers, staging copies)") +
                (hostCoherent_ ? ", host-coherent" : ", not host-coherent (explicit flush and invalidate)") +
                (fillsNewBuffers() ? ", new buffers filled with NaN bytes" : ""));
  std::string fallbacks;
  auto add = [&](const std::string& s) { fallbacks += (fallbacks.empty() ? "" : "; ") + s; };
  if (!f.bufferFloatAtomicAdd) add("no float atomics: gradients summed without them");
  if (!f.subgroupArithmetic || !f.subgroupVote) add("no subgroup arithmetic/vote: reductions in shared memory");
  if (texelsAsStorage_) add("texel buffers too small: tables bound as storage buffers");
  if (!unified_) add("staging copies for uploads and downloads");
  out.push_back("fallbacks: " + (fallbacks.empty() ? std::string("none") : fallbacks));
  return out;
}

int Device::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const {
  for (uint32_t i = 0; i < memProps_.memoryTypeCount; ++i)
    if ((typeBits & (1u << i)) && (memProps_.memoryTypes[i].propertyFlags & required) == required) return int(i);
  return -1;
}

void Device::runOnce(const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd;
  check(vkAllocateCommandBuffers(device_, &ai, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vkBeginCommandBuffer(cmd, &bi);
  // Submission order orders execution, not memory: what earlier submissions wrote is made visible
  // to these commands, and what these write to the host that reads it after the fence.
  recordMemoryBarrier(cmd, kDeviceStages, kDeviceStages);
  record(cmd);
  recordMemoryBarrier(cmd, kDeviceStages, VK_PIPELINE_STAGE_HOST_BIT);
  vkEndCommandBuffer(cmd);
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence;
  check(vkCreateFence(device_, &fi, nullptr, &fence), "vkCreateFence");
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  VkResult r = vkQueueSubmit(queue_, 1, &si, fence);
  if (r == VK_SUCCESS) r = vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX);
  ++hostWaits_;
  vkDestroyFence(device_, fence, nullptr);
  vkFreeCommandBuffers(device_, pool_, 1, &cmd);
  check(r, "vkQueueSubmit/vkWaitForFences");
}

}  // namespace vknerf::gpu

#pragma once
// Device profiles: lavapipe made to behave like another class of Vulkan device, so that the paths
// a real GPU takes run (and are tested) on a CPU-only machine. A profile hides optional features,
// lowers limits to what that class reports, and forces its memory model: device-local buffers the
// host never maps (reached through staging copies), host memory that is not coherent (explicit
// flush and invalidate), and fresh buffers filled with NaN bytes (a GPU's new memory holds garbage,
// lavapipe's fresh pages are zero). Chosen by VKNERF_DEVICE_PROFILE=NAME or ContextOptions::profile.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>
#include <vector>

namespace vknerf::gpu {

// How the host reaches device buffers.
enum class MemoryModel {
  Unified,   // buffers live in device-local, host-visible memory mapped once (integrated GPUs, lavapipe)
  Discrete,  // buffers are device-local only; uploads and downloads go through staging buffers
};

struct DeviceProfile {
  const char* name;
  const char* source;  // where the numbers come from
  // Features the class lacks (hidden even where lavapipe has them).
  bool floatAtomicAdd, subgroupArithmetic, subgroupVote, int64;
  // Limits as the class reports them; the device gets the smaller of these and its own.
  uint32_t maxComputeWorkGroupCount[3];
  uint32_t maxComputeWorkGroupInvocations;
  uint32_t maxComputeSharedMemorySize;
  uint32_t maxStorageBufferRange;
  uint32_t maxTexelBufferElements;
  uint32_t maxPushConstantsSize;
  uint32_t maxPerStageDescriptorStorageBuffers;
  uint32_t maxMemoryAllocationCount;
  // Alignments as the class reports them; the device gets the larger of these and its own.
  VkDeviceSize minStorageBufferOffsetAlignment, minTexelBufferOffsetAlignment, nonCoherentAtomSize;
  uint32_t subgroupSize;  // 0: the device's own
  MemoryModel memory;
  bool hostCoherent;  // false: mapped memory is flushed after host writes and invalidated before host reads
};

// The profile named `name`; throws vknerf::Error listing the names when there is none.
const DeviceProfile& deviceProfile(const std::string& name);
const std::vector<DeviceProfile>& deviceProfiles();
// ContextOptions::profile if set, else VKNERF_DEVICE_PROFILE, else "" (the device as it is; so is
// "none" in either).
std::string requestedProfile(const std::string& option);

// The limits lowered (and alignments raised) to the profile's.
void applyProfileLimits(const DeviceProfile& p, VkPhysicalDeviceLimits& limits);

}  // namespace vknerf::gpu

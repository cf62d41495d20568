#include "gpu/device/device_profile.h"

#include <algorithm>
#include <cstdlib>

#include "vknerf/error.h"

namespace vknerf::gpu {
namespace {

constexpr uint32_t kU32Max = 0xFFFFFFFFu;

// Each profile: the features the class lacks, its limits and its memory. The numbers are what the
// named devices' drivers report (gpuinfo.org's Vulkan reports for them; MoltenVK's from its
// MVKDevice.mm), rounded towards the stricter value where reports of one class differ.
const std::vector<DeviceProfile> kProfiles = {
    // Vulkan 1.2's required limits (the spec's "Required Limits" table) and no optional feature:
    // no float atomics, subgroups reduced to the basic operations every 1.1 device has, no int64.
    // Two limits are vknerf's own floor instead of the spec's, because its kernels cannot go lower:
    // 256 invocations per workgroup (spec: 128) and 16 storage buffers per stage (spec: 4). Every
    // class below reports far more, and Device refuses a device under them with one line.
    {"minimum", "Vulkan 1.2 specification, Required Limits (vknerf's floor for two of them)",
     false, false, false, false,
     {65535, 65535, 65535}, 256, 16384, 1u << 27, 65536, 128, 16, 4096,
     256, 256, 256, 0, MemoryModel::Discrete, false},
    // GeForce RTX 3080 / 4090 on the 535 Linux driver: a 2^31-1 x group count, 4 GiB storage range,
    // 2^27 texels; host-visible types are coherent. 4096 allocations is the Windows driver's limit.
    {"nvidia", "gpuinfo.org reports: GeForce RTX 3080 / RTX 4090, NVIDIA 535.x, Linux and Windows",
     true, true, true, true,
     {2147483647u, 65535, 65535}, 1024, 49152, kU32Max, 1u << 27, 256, 1048576, 4096,
     16, 16, 64, 32, MemoryModel::Discrete, true},
    // Radeon RX 6800 (gfx10.3) on RADV: float atomic add on buffers only from RDNA3 on; wave64 in
    // compute; storage and texel ranges of 2^32-1.
    {"amd-rdna2", "gpuinfo.org reports: AMD Radeon RX 6800 / 6700 XT, RADV (Mesa 22.3-23.x)",
     false, true, true, true,
     {kU32Max, 65535, 65535}, 1024, 65536, kU32Max, kU32Max, 256, 8388606, kU32Max,
     4, 4, 64, 64, MemoryModel::Discrete, true},
    // Iris Xe (Tiger Lake, Xe-LP) on ANV: integrated (one coherent, cached heap the host maps), no
    // buffer float atomic add (ANV has it from Xe-HPG / Arc on), 1 GiB storage range.
    {"intel-xe-lp", "gpuinfo.org reports: Intel Iris Xe Graphics (TGL GT2), ANV (Mesa 22.3-23.x)",
     false, true, true, true,
     {65535, 65535, 65535}, 1024, 65536, 1u << 30, 1u << 27, 128, 64, kU32Max,
     64, 64, 64, 32, MemoryModel::Unified, true},
    // Mali-G78 (Valhall) on Arm's driver: integrated, but its cached host memory is not coherent;
    // 65536 texels per texel buffer (1 MiB of rgba32f), 128 MiB storage range, 512 invocations.
    {"mali", "gpuinfo.org reports: Arm Mali-G78 / G710, Arm driver r38-r44, Android",
     false, true, true, true,
     {65535, 65535, 65535}, 512, 32768, 1u << 27, 65536, 128, 35, 4096,
     16, 16, 64, 16, MemoryModel::Unified, false},
    // Apple M1 / M2 through MoltenVK 1.2: large group counts (kMVKUndefinedLargeUInt32), 32 KiB of
    // workgroup memory on macOS, 4 KiB of push constants; float atomic add only on Metal 3 systems.
    {"apple", "MoltenVK 1.2 MVKDevice.mm; gpuinfo.org reports: Apple M1 / M2, macOS 13",
     false, true, true, true,
     {1073741823u, 1073741823u, 1073741823u}, 1024, 32768, 1073741823u, 1u << 26, 4096, 1024, 1073741823u,
     16, 16, 16, 32, MemoryModel::Unified, true},
};

}  // namespace

const std::vector<DeviceProfile>& deviceProfiles() { return kProfiles; }

const DeviceProfile& deviceProfile(const std::string& name) {
  std::string names;
  for (const auto& p : kProfiles) {
    if (name == p.name) return p;
    names += (names.empty() ? "" : ", ") + std::string(p.name);
  }
  throw Error("unknown device profile '" + name + "' (VKNERF_DEVICE_PROFILE / ContextOptions::profile; profiles: " +
              names + ")");
}

std::string requestedProfile(const std::string& option) {
  const char* env = std::getenv("VKNERF_DEVICE_PROFILE");
  const std::string name = !option.empty() ? option : env ? env : "";
  return name == "none" ? "" : name;
}

void applyProfileLimits(const DeviceProfile& p, VkPhysicalDeviceLimits& l) {
  auto lower = [](uint32_t& v, uint32_t to) { v = std::min(v, to); };
  auto raise = [](VkDeviceSize& v, VkDeviceSize to) { v = std::max(v, to); };
  for (int i = 0; i < 3; ++i) lower(l.maxComputeWorkGroupCount[i], p.maxComputeWorkGroupCount[i]);
  lower(l.maxComputeWorkGroupInvocations, p.maxComputeWorkGroupInvocations);
  for (int i = 0; i < 3; ++i) lower(l.maxComputeWorkGroupSize[i], p.maxComputeWorkGroupInvocations);
  lower(l.maxComputeSharedMemorySize, p.maxComputeSharedMemorySize);
  lower(l.maxStorageBufferRange, p.maxStorageBufferRange);
  lower(l.maxTexelBufferElements, p.maxTexelBufferElements);
  lower(l.maxPushConstantsSize, p.maxPushConstantsSize);
  lower(l.maxPerStageDescriptorStorageBuffers, p.maxPerStageDescriptorStorageBuffers);
  lower(l.maxMemoryAllocationCount, p.maxMemoryAllocationCount);
  raise(l.minStorageBufferOffsetAlignment, p.minStorageBufferOffsetAlignment);
  raise(l.minTexelBufferOffsetAlignment, p.minTexelBufferOffsetAlignment);
  raise(l.nonCoherentAtomSize, p.nonCoherentAtomSize);
}

}  // namespace vknerf::gpu

#pragma once
// What a kernel asks of a device, checked against the limits in force (a profile's included) in
// one place: its push constants, its bindings per stage, its workgroup size, its group counts and
// its binding offsets. A kernel that asks too much fails with one line naming the kernel and the
// limit, instead of an invalid pipeline or dispatch that a GPU driver may crash on.
#include <vulkan/vulkan.h>

#include <array>
#include <string>
#include <cstdint>

#include "gpu/kernels/kernel.h"

namespace vknerf::gpu {

class Device;

// `desc` as `dev` runs it: where the device binds texel buffers as storage buffers
// (Device::texelsAsStorage), the shader's storage twin and Storage bindings.
KernelDesc adaptToDevice(const Device& dev, KernelDesc desc);

// The workgroup size of a compute shader's SPIR-V (its LocalSize execution mode); {0,0,0} if it
// declares none (LocalSizeId: spec constants).
std::array<uint32_t, 3> spirvLocalSize(const ShaderCode& code);

// Throws vknerf::Error when the kernel's push constants, bindings or workgroup size pass `limits`.
// "kernel NAME": how every error about one kernel begins.
std::string kernelName(const char* shader);
std::string kernelName(const KernelDesc& desc);

void checkKernelLimits(const VkPhysicalDeviceLimits& limits, const KernelDesc& desc);
// Throws vknerf::Error when a dispatch's group counts pass maxComputeWorkGroupCount.
void checkGroupCounts(const VkPhysicalDeviceLimits& limits, const char* kernel, uint32_t gx, uint32_t gy, uint32_t gz);
// Throws vknerf::Error when a binding's offset is not a multiple of the device's alignment for it.
void checkBindingOffset(const VkPhysicalDeviceLimits& limits, const char* kernel, size_t binding, Binding type,
                        VkDeviceSize offset);

}  // namespace vknerf::gpu

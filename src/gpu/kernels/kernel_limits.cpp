#include "gpu/kernels/kernel_limits.h"

#include <string>

#include "gpu/device/device.h"
#include "vknerf/error.h"

namespace vknerf::gpu {
std::string kernelName(const char* shader) { return std::string("kernel ") + shader; }
std::string kernelName(const KernelDesc& d) { return kernelName(d.shader.name); }

KernelDesc adaptToDevice(const Device& dev, KernelDesc desc) {
  if (!dev.texelsAsStorage()) return desc;
  bool texels = false;
  for (Binding& b : desc.bindings)
    if (b == Binding::TexelRgba32f) b = Binding::Storage, texels = true;
  if (!texels) return desc;
  if (!desc.shader.storageWords) throw Error(kernelName(desc) + " has no storage-buffer variant");
  desc.shader.words = desc.shader.storageWords;
  desc.shader.wordCount = desc.shader.storageWordCount;
  return desc;
}

std::array<uint32_t, 3> spirvLocalSize(const ShaderCode& code) {
  // SPIR-V: a 5-word header, then instructions whose first word is (word count << 16) | opcode.
  constexpr uint32_t kOpExecutionMode = 16, kLocalSize = 17;
  for (size_t i = 5; i < code.wordCount;) {
    const uint32_t words = code.words[i] >> 16, op = code.words[i] & 0xFFFF;
    if (words == 0) break;
    if (op == kOpExecutionMode && words >= 6 && code.words[i + 2] == kLocalSize)
      return {code.words[i + 3], code.words[i + 4], code.words[i + 5]};
    i += words;
  }
  return {0, 0, 0};
}

void checkKernelLimits(const VkPhysicalDeviceLimits& l, const KernelDesc& d) {
  auto over = [&](const std::string& what, uint64_t has, uint64_t limit, const char* name) {
    if (has > limit)
      throw Error(kernelName(d) + ": " + what + " " + std::to_string(has) + " exceeds the device's " + name + " " +
                  std::to_string(limit));
  };
  over("push constants of", d.pushConstantBytes, l.maxPushConstantsSize, "maxPushConstantsSize");
  uint32_t storage = 0, images = 0;
  for (Binding b : d.bindings) (b == Binding::Storage ? storage : images)++;
  over("storage buffers", storage, l.maxPerStageDescriptorStorageBuffers, "maxPerStageDescriptorStorageBuffers");
  // Storage texel buffers and storage images share one per-stage limit.
  over("storage images and texel buffers", images, l.maxPerStageDescriptorStorageImages,
       "maxPerStageDescriptorStorageImages");
  const auto size = spirvLocalSize(d.shader);
  for (int i = 0; i < 3; ++i)
    over("workgroup size[" + std::to_string(i) + "]", size[i], l.maxComputeWorkGroupSize[i], "maxComputeWorkGroupSize");
  over("workgroup of", uint64_t(size[0]) * size[1] * size[2], l.maxComputeWorkGroupInvocations,
       "maxComputeWorkGroupInvocations");
}

void checkGroupCounts(const VkPhysicalDeviceLimits& l, const char* kernel, uint32_t gx, uint32_t gy, uint32_t gz) {
  const uint32_t g[3] = {gx, gy, gz};
  for (int i = 0; i < 3; ++i)
    if (g[i] > l.maxComputeWorkGroupCount[i])
      throw Error(kernelName(kernel) + ": " + std::to_string(g[i]) + " workgroups along axis " +
                  std::to_string(i) + " exceed the device's maxComputeWorkGroupCount[" + std::to_string(i) + "] " +
                  std::to_string(l.maxComputeWorkGroupCount[i]) + "; split the dispatch");
}

void checkBindingOffset(const VkPhysicalDeviceLimits& l, const char* kernel, size_t binding, Binding type,
                        VkDeviceSize offset) {
  const VkDeviceSize align = type == Binding::TexelRgba32f ? l.minTexelBufferOffsetAlignment : l.minStorageBufferOffsetAlignment;
  if (align > 1 && offset % align)
    throw Error(kernelName(kernel) + ": binding " + std::to_string(binding) + " starts at byte " +
                std::to_string(offset) + ", not a multiple of the device's " +
                (type == Binding::TexelRgba32f ? "minTexelBufferOffsetAlignment " : "minStorageBufferOffsetAlignment ") +
                std::to_string(align));
}

}  // namespace vknerf::gpu

#include "gpu/compile/compile_device.h"

#include <string>

#include "gpu/kernels/kernel_limits.h"
#include "gpu/device/vk_check.h"

namespace vknerf::gpu {
namespace {

// Stand-in sizes: 16 texels (a power of two) and 17, in rgba32f.
constexpr VkDeviceSize kPow2Bytes = 256, kOtherBytes = 272, kStorageBytes = 256;
constexpr uint32_t kMaxBindings = 64;  // per kind, in the one descriptor set

VkBuffer makeBuffer(VkDevice dev, VkDeviceSize bytes, VkBufferUsageFlags usage) {
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = bytes;
  bi.usage = usage;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer b = VK_NULL_HANDLE;
  check(vkCreateBuffer(dev, &bi, nullptr, &b), "vkCreateBuffer (compiling device)");
  return b;
}

VkBufferView makeView(VkDevice dev, VkBuffer buffer) {
  VkBufferViewCreateInfo vi{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  vi.buffer = buffer;
  vi.format = VK_FORMAT_R32G32B32A32_SFLOAT;
  vi.range = VK_WHOLE_SIZE;
  VkBufferView v = VK_NULL_HANDLE;
  check(vkCreateBufferView(dev, &vi, nullptr, &v), "vkCreateBufferView (compiling device)");
  return v;
}

}  // namespace

CompileDevice::CompileDevice(VkPhysicalDevice physical, uint32_t queueFamily, const KernelFeatures& features) {
  try {
    device_ = createComputeDevice(physical, queueFamily, features);
    vkGetDeviceQueue(device_, queueFamily, 0, &queue_);
    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = queueFamily;
    check(vkCreateCommandPool(device_, &pi, nullptr, &pool_), "vkCreateCommandPool (compiling device)");
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    check(vkAllocateCommandBuffers(device_, &ai, &cmd_), "vkAllocateCommandBuffers (compiling device)");
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    check(vkCreateFence(device_, &fi, nullptr, &fence_), "vkCreateFence (compiling device)");

    storage_ = makeBuffer(device_, kStorageBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    texelPow2_ = makeBuffer(device_, kPow2Bytes, VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT);
    texelOther_ = makeBuffer(device_, kOtherBytes, VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT);
    // One allocation holds the three, each at its alignment.
    VkDeviceSize offsets[3], end = 0;
    uint32_t types = ~0u;
    const VkBuffer buffers[3] = {storage_, texelPow2_, texelOther_};
    for (int i = 0; i < 3; ++i) {
      VkMemoryRequirements req;
      vkGetBufferMemoryRequirements(device_, buffers[i], &req);
      offsets[i] = (end + req.alignment - 1) / req.alignment * req.alignment;
      end = offsets[i] + req.size;
      types &= req.memoryTypeBits;
    }
    if (!types) throw Error("compiling device: no memory type holds both storage and texel buffers");
    VkMemoryAllocateInfo mi{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mi.allocationSize = end;
    mi.memoryTypeIndex = uint32_t(__builtin_ctz(types));
    check(vkAllocateMemory(device_, &mi, nullptr, &memory_), "vkAllocateMemory (compiling device)");
    for (int i = 0; i < 3; ++i)
      check(vkBindBufferMemory(device_, buffers[i], memory_, offsets[i]), "vkBindBufferMemory (compiling device)");
    viewPow2_ = makeView(device_, texelPow2_);
    viewOther_ = makeView(device_, texelOther_);

    VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kMaxBindings},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, kMaxBindings}};
    VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpi.maxSets = 1;
    dpi.poolSizeCount = 2;
    dpi.pPoolSizes = sizes;
    check(vkCreateDescriptorPool(device_, &dpi, nullptr, &descriptors_), "vkCreateDescriptorPool (compiling device)");
  } catch (...) {
    release();
    throw;
  }
}

CompileDevice::~CompileDevice() { release(); }

void CompileDevice::release() {
  if (!device_) return;
  vkDeviceWaitIdle(device_);
  if (descriptors_) vkDestroyDescriptorPool(device_, descriptors_, nullptr);
  for (VkBufferView v : {viewPow2_, viewOther_})
    if (v) vkDestroyBufferView(device_, v, nullptr);
  for (VkBuffer b : {storage_, texelPow2_, texelOther_})
    if (b) vkDestroyBuffer(device_, b, nullptr);
  if (memory_) vkFreeMemory(device_, memory_, nullptr);
  if (fence_) vkDestroyFence(device_, fence_, nullptr);
  if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);  // frees cmd_
  vkDestroyDevice(device_, nullptr);
  device_ = VK_NULL_HANDLE;
}

void CompileDevice::compile(const KernelVariant& k) {
  const auto& bindings = k.desc.bindings;
  if (bindings.size() > kMaxBindings)
    throw Error(kernelName(k.desc) + ": too many bindings to compile ahead");
  for (Binding b : bindings)
    if (b == Binding::StorageImage)
      throw Error(kernelName(k.desc) + " binds a caller's image: it cannot be compiled ahead");
  PipelineObjects p = PipelineObjects::create(device_, VK_NULL_HANDLE, k.desc);
  struct Cleanup {
    CompileDevice& d;
    PipelineObjects& p;
    ~Cleanup() {
      vkResetDescriptorPool(d.device_, d.descriptors_, 0);
      p.destroy(d.device_);
    }
  } cleanup{*this, p};

  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = descriptors_;
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &p.setLayout;
  VkDescriptorSet set = VK_NULL_HANDLE;
  check(vkAllocateDescriptorSets(device_, &ai, &set), "vkAllocateDescriptorSets (compiling device)");
  const VkDescriptorBufferInfo storage{storage_, 0, VK_WHOLE_SIZE};
  std::vector<VkWriteDescriptorSet> writes(bindings.size());
  for (uint32_t i = 0; i < bindings.size(); ++i) {
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = i;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = descriptorType(bindings[i]);
    if (bindings[i] == Binding::Storage) writes[i].pBufferInfo = &storage;
    else writes[i].pTexelBufferView = (k.texelPow2 >> i) & 1 ? &viewPow2_ : &viewOther_;
  }
  vkUpdateDescriptorSets(device_, uint32_t(writes.size()), writes.data(), 0, nullptr);

  check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer (compiling device)");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd_, &bi), "vkBeginCommandBuffer (compiling device)");
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, p.pipeline);
  vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, p.layout, 0, 1, &set, 0, nullptr);
  if (k.desc.pushConstantBytes) {
    zeros_.resize(k.desc.pushConstantBytes, 0);
    vkCmdPushConstants(cmd_, p.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, k.desc.pushConstantBytes, zeros_.data());
  }
  vkCmdDispatch(cmd_, 0, 0, 0);  // no workgroups: the stand-ins are never read, the pipeline compiles
  check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer (compiling device)");
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd_;
  check(vkResetFences(device_, 1, &fence_), "vkResetFences (compiling device)");
  check(vkQueueSubmit(queue_, 1, &si, fence_), "vkQueueSubmit (compiling device)");
  check(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences (compiling device)");
}

}  // namespace vknerf::gpu

#include "gpu/kernels/kernel.h"

#include <bit>
#include <chrono>
#include <utility>

#include "gpu/device/device.h"
#include "gpu/compile/kernel_compiler.h"
#include "gpu/kernels/kernel_limits.h"
#include "gpu/device/vk_check.h"

namespace vknerf::gpu {
namespace {
constexpr uint32_t kSetsPerPool = 64;

void requireBindingCount(const KernelDesc& d, size_t n) {
  if (n != d.bindings.size())
    throw Error(kernelName(d) + " takes " + std::to_string(d.bindings.size()) + " buffers, got " +
                std::to_string(n));
}

// The storage-buffer range a binding spans, checked against maxStorageBufferRange.
VkDeviceSize storageRange(const Context& ctx, const KernelDesc& d, size_t i, const BufferRange& b, VkDeviceSize size) {
  VkDeviceSize range = b.range == VK_WHOLE_SIZE ? size - b.offset : b.range;
  range = std::max<VkDeviceSize>(range, 16);  // empty arrays bind a valid minimal range
  const auto limit = ctx.properties().limits.maxStorageBufferRange;
  if (range > limit)
    throw Error(kernelName(d) + ": binding " + std::to_string(i) + " spans " + std::to_string(range) +
                " bytes, over maxStorageBufferRange " + std::to_string(limit) + "; split the batch");
  return range;
}

// The range a cached set binds: the requested one rounded up to a power of two, within the buffer
// and the device's limits. A training step binds ranges sized by its ray and sample counts; keyed
// by the exact range, the cache would add a set (and its texel views) for every new count, without
// bound over a long run. Rounded, a (buffer, offset) pair has a few dozen ranges at most. Kernels
// read only the rows their counts name (row limits, push constants), never the binding's length.
VkDeviceSize cachedRange(const Context& ctx, Binding kind, const BufferRange& b) {
  if (b.range == VK_WHOLE_SIZE || b.offset >= b.buffer->size()) return b.range;
  const auto& limits = ctx.properties().limits;
  const VkDeviceSize limit =
      kind == Binding::Storage ? limits.maxStorageBufferRange : VkDeviceSize(limits.maxTexelBufferElements) * 16;
  const VkDeviceSize rounded = std::min({std::bit_ceil(std::max<VkDeviceSize>(b.range, 16)), b.buffer->size() - b.offset, limit});
  return std::max(rounded, b.range);  // a range over a limit stays as it is, for its error below
}
}  // namespace

VkDescriptorType descriptorType(Binding b) {
  switch (b) {
    case Binding::Storage: return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    case Binding::TexelRgba32f: return VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
    case Binding::StorageImage: return VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  }
  return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}

PipelineObjects PipelineObjects::create(VkDevice dev, VkPipelineCache cache, const KernelDesc& desc) {
  PipelineObjects o;
  try {
    VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    mi.codeSize = desc.shader.wordCount * sizeof(uint32_t);
    mi.pCode = desc.shader.words;
    check(vkCreateShaderModule(dev, &mi, nullptr, &o.module),
          (std::string("vkCreateShaderModule(") + desc.shader.name + ")").c_str());

    std::vector<VkDescriptorSetLayoutBinding> lb;
    for (uint32_t i = 0; i < desc.bindings.size(); ++i)
      lb.push_back({i, descriptorType(desc.bindings[i]), 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    li.bindingCount = uint32_t(lb.size());
    li.pBindings = lb.data();
    check(vkCreateDescriptorSetLayout(dev, &li, nullptr, &o.setLayout), "vkCreateDescriptorSetLayout");

    VkPushConstantRange pcr{VK_SHADER_STAGE_COMPUTE_BIT, 0, desc.pushConstantBytes};
    VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    pli.setLayoutCount = 1;
    pli.pSetLayouts = &o.setLayout;
    pli.pushConstantRangeCount = desc.pushConstantBytes ? 1 : 0;
    pli.pPushConstantRanges = &pcr;
    check(vkCreatePipelineLayout(dev, &pli, nullptr, &o.layout), "vkCreatePipelineLayout");

    std::vector<VkSpecializationMapEntry> entries;
    std::vector<uint32_t> values;
    for (const SpecConstant& s : desc.specialization) {
      entries.push_back({s.id, uint32_t(values.size() * 4), 4});
      values.push_back(s.value);
    }
    VkSpecializationInfo si{uint32_t(entries.size()), entries.data(), values.size() * 4, values.data()};
    VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    ci.stage.module = o.module;
    ci.stage.pName = "main";
    ci.stage.pSpecializationInfo = entries.empty() ? nullptr : &si;
    ci.layout = o.layout;
    check(vkCreateComputePipelines(dev, cache, 1, &ci, nullptr, &o.pipeline),
          (std::string("vkCreateComputePipelines(") + desc.shader.name + ")").c_str());
  } catch (...) {
    o.destroy(dev);
    throw;
  }
  return o;
}

void PipelineObjects::destroy(VkDevice dev) {
  if (pipeline) vkDestroyPipeline(dev, pipeline, nullptr);
  if (layout) vkDestroyPipelineLayout(dev, layout, nullptr);
  if (setLayout) vkDestroyDescriptorSetLayout(dev, setLayout, nullptr);
  if (module) vkDestroyShaderModule(dev, module, nullptr);
  *this = {};
}

Kernel::Kernel(Context& ctx, KernelDesc desc) : ctx_(&ctx), desc_(adaptToDevice(device(ctx), std::move(desc))) {
  if (!desc_.shader.words) throw Error("kernel without a shader");
  checkKernelLimits(ctx.properties().limits, desc_);
  // Drivers other than lavapipe compile here: the time counts as compiling (KernelCompiler).
  const auto start = std::chrono::steady_clock::now();
  objects_ = PipelineObjects::create(ctx.device(), device(ctx).pipelineCache(), desc_);
  device(ctx).compiler().countPipeline(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

Kernel::~Kernel() { destroy(); }

void Kernel::destroy() {
  if (!ctx_) return;
  VkDevice dev = ctx_->device();
  device(*ctx_).cachedDescriptorSets() -= sets_.size();
  for (auto v : views_) vkDestroyBufferView(dev, v, nullptr);
  for (auto p : pools_) vkDestroyDescriptorPool(dev, p, nullptr);
  if (transientPool_) vkDestroyDescriptorPool(dev, transientPool_, nullptr);
  objects_.destroy(dev);
  views_.clear();
  pools_.clear();
  sets_.clear();
  transientPool_ = VK_NULL_HANDLE;
  transientSets_.clear();
  nextTransient_ = 0;
  ctx_ = nullptr;
}

Kernel& Kernel::operator=(Kernel&& o) noexcept {
  if (this != &o) {
    destroy();
    ctx_ = std::exchange(o.ctx_, nullptr);
    desc_ = std::move(o.desc_);
    objects_ = std::exchange(o.objects_, {});
    pools_ = std::move(o.pools_);
    setsInLastPool_ = o.setsInLastPool_;
    views_ = std::move(o.views_);
    sets_ = std::move(o.sets_);
    transientPool_ = std::exchange(o.transientPool_, VK_NULL_HANDLE);
    transientSets_ = std::move(o.transientSets_);
    nextTransient_ = o.nextTransient_;
  }
  return *this;
}

VkDescriptorSet Kernel::descriptorSet(std::span<const BufferRange> bindings) {
  requireBindingCount(desc_, bindings.size());
  for (size_t i = 0; i < bindings.size(); ++i)
    if (bindings[i].isExternal() || desc_.bindings[i] == Binding::StorageImage)
      throw Error(kernelName(desc_) + ": binding " + std::to_string(i) +
                  " is a caller's resource; bind it through Kernel::transientSet");
  std::vector<BufferRange> bound(bindings.begin(), bindings.end());
  std::vector<uint64_t> key;
  for (size_t i = 0; i < bound.size(); ++i) {
    bound[i].range = cachedRange(*ctx_, desc_.bindings[i], bound[i]);
    key.insert(key.end(), {bound[i].buffer->id(), bound[i].offset, bound[i].range});
  }
  if (auto it = sets_.find(key); it != sets_.end()) return it->second;

  VkDevice dev = ctx_->device();
  if (pools_.empty() || setsInLastPool_ == kSetsPerPool) {
    VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kSetsPerPool * 16},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, kSetsPerPool * 16}};
    VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pi.maxSets = kSetsPerPool;
    pi.poolSizeCount = 2;
    pi.pPoolSizes = sizes;
    VkDescriptorPool pool;
    check(vkCreateDescriptorPool(dev, &pi, nullptr, &pool), "vkCreateDescriptorPool");
    pools_.push_back(pool);
    setsInLastPool_ = 0;
  }
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = pools_.back();
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &objects_.setLayout;
  VkDescriptorSet set;
  check(vkAllocateDescriptorSets(dev, &ai, &set), "vkAllocateDescriptorSets");
  ++setsInLastPool_;

  const auto& limits = ctx_->properties().limits;
  std::vector<VkDescriptorBufferInfo> infos(bindings.size());
  std::vector<VkBufferView> views(bindings.size(), VK_NULL_HANDLE);
  std::vector<VkWriteDescriptorSet> writes(bindings.size());
  for (size_t i = 0; i < bound.size(); ++i) {
    const BufferRange& b = bound[i];
    VkDeviceSize range = b.range == VK_WHOLE_SIZE ? b.buffer->size() - b.offset : b.range;
    range = std::max<VkDeviceSize>(range, 16);  // empty arrays bind a valid minimal range
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = uint32_t(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = descriptorType(desc_.bindings[i]);
    checkBindingOffset(limits, desc_.shader.name, i, desc_.bindings[i], b.offset);
    if (desc_.bindings[i] == Binding::Storage) {
      range = storageRange(*ctx_, desc_, i, b, b.buffer->size());
      infos[i] = {b.buffer->handle(), b.offset, range};
      writes[i].pBufferInfo = &infos[i];
    } else {
      VkBufferViewCreateInfo vi{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
      vi.buffer = b.buffer->handle();
      vi.format = VK_FORMAT_R32G32B32A32_SFLOAT;
      vi.offset = b.offset;
      vi.range = range / 16 * 16;
      uint64_t texels = vi.range / 16;
      if (texels > limits.maxTexelBufferElements)
        throw Error(kernelName(desc_) + ": texel binding " + std::to_string(i) + " holds " + std::to_string(texels) +
                    " texels, over maxTexelBufferElements; split the batch");
      check(vkCreateBufferView(dev, &vi, nullptr, &views[i]), "vkCreateBufferView");
      views_.push_back(views[i]);
      writes[i].pTexelBufferView = &views[i];
    }
  }
  vkUpdateDescriptorSets(dev, uint32_t(writes.size()), writes.data(), 0, nullptr);
  sets_.emplace(std::move(key), set);
  device(*ctx_).cachedDescriptorSets()++;
  return set;
}

VkDescriptorSet Kernel::transientSet(std::span<const BufferRange> bindings) {
  requireBindingCount(desc_, bindings.size());
  VkDevice dev = ctx_->device();
  if (transientSets_.empty()) {
    const uint32_t n = uint32_t(desc_.bindings.size());
    VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kTransientSets * n},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kTransientSets * n}};
    VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pi.maxSets = kTransientSets;
    pi.poolSizeCount = 2;
    pi.pPoolSizes = sizes;
    check(vkCreateDescriptorPool(dev, &pi, nullptr, &transientPool_), "vkCreateDescriptorPool");
    std::vector<VkDescriptorSetLayout> layouts(kTransientSets, objects_.setLayout);
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = transientPool_;
    ai.descriptorSetCount = kTransientSets;
    ai.pSetLayouts = layouts.data();
    transientSets_.resize(kTransientSets);
    VkResult r = vkAllocateDescriptorSets(dev, &ai, transientSets_.data());
    if (r != VK_SUCCESS) transientSets_.clear();
    check(r, "vkAllocateDescriptorSets");
  }

  std::vector<VkDescriptorBufferInfo> buffers(bindings.size());
  std::vector<VkDescriptorImageInfo> images(bindings.size());
  std::vector<VkWriteDescriptorSet> writes(bindings.size());
  VkDescriptorSet set = transientSets_[nextTransient_];
  for (size_t i = 0; i < bindings.size(); ++i) {
    const BufferRange& b = bindings[i];
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = uint32_t(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = descriptorType(desc_.bindings[i]);
    const std::string where = kernelName(desc_) + ": binding " + std::to_string(i);
    switch (desc_.bindings[i]) {
      case Binding::Storage: {
        if (b.image || !b.handle()) throw Error(where + " needs a buffer");
        checkBindingOffset(ctx_->properties().limits, desc_.shader.name, i, Binding::Storage, b.offset);
        if (!b.buffer && b.range == VK_WHOLE_SIZE) throw Error(where + ": a caller's buffer binds an explicit range");
        const VkDeviceSize range = storageRange(*ctx_, desc_, i, b, b.buffer ? b.buffer->size() : b.range);
        buffers[i] = {b.handle(), b.offset, range};
        writes[i].pBufferInfo = &buffers[i];
        break;
      }
      case Binding::StorageImage:
        if (!b.image) throw Error(where + " needs a storage image view");
        images[i] = {VK_NULL_HANDLE, b.image, VK_IMAGE_LAYOUT_GENERAL};
        writes[i].pImageInfo = &images[i];
        break;
      case Binding::TexelRgba32f:
        throw Error(where + ": texel buffers are not supported in transient sets");
    }
  }
  vkUpdateDescriptorSets(dev, uint32_t(writes.size()), writes.data(), 0, nullptr);
  nextTransient_ = (nextTransient_ + 1) % kTransientSets;
  return set;
}

}  // namespace vknerf::gpu

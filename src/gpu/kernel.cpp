#include "gpu/kernel.h"

#include <utility>

#include "gpu/vk_check.h"

namespace vknerf::gpu {
namespace {
constexpr uint32_t kSetsPerPool = 64;

VkDescriptorType descriptorType(Binding b) {
  return b == Binding::Storage ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
}
}  // namespace

Kernel::Kernel(Context& ctx, KernelDesc desc) : ctx_(&ctx), desc_(std::move(desc)) {
  auto code = findShader(desc_.shader);
  if (code.empty()) throw Error("no embedded shader named '" + desc_.shader + "'");
  VkDevice dev = ctx.device();

  VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  mi.codeSize = code.size_bytes();
  mi.pCode = code.data();
  check(vkCreateShaderModule(dev, &mi, nullptr, &module_), ("vkCreateShaderModule(" + desc_.shader + ")").c_str());

  std::vector<VkDescriptorSetLayoutBinding> lb;
  for (uint32_t i = 0; i < desc_.bindings.size(); ++i)
    lb.push_back({i, descriptorType(desc_.bindings[i]), 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
  VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  li.bindingCount = uint32_t(lb.size());
  li.pBindings = lb.data();
  check(vkCreateDescriptorSetLayout(dev, &li, nullptr, &setLayout_), "vkCreateDescriptorSetLayout");

  VkPushConstantRange pcr{VK_SHADER_STAGE_COMPUTE_BIT, 0, desc_.pushConstantBytes};
  VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pli.setLayoutCount = 1;
  pli.pSetLayouts = &setLayout_;
  pli.pushConstantRangeCount = desc_.pushConstantBytes ? 1 : 0;
  pli.pPushConstantRanges = &pcr;
  check(vkCreatePipelineLayout(dev, &pli, nullptr, &layout_), "vkCreatePipelineLayout");

  std::vector<VkSpecializationMapEntry> entries;
  for (uint32_t i = 0; i < desc_.specialization.size(); ++i) entries.push_back({i, i * 4u, 4});
  VkSpecializationInfo si{uint32_t(entries.size()), entries.data(), desc_.specialization.size() * 4, desc_.specialization.data()};
  VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  ci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = module_;
  ci.stage.pName = "main";
  ci.stage.pSpecializationInfo = entries.empty() ? nullptr : &si;
  ci.layout = layout_;
  check(vkCreateComputePipelines(dev, ctx.pipelineCache(), 1, &ci, nullptr, &pipeline_),
        ("vkCreateComputePipelines(" + desc_.shader + ")").c_str());
}

Kernel::~Kernel() { destroy(); }

void Kernel::destroy() {
  if (!ctx_) return;
  VkDevice dev = ctx_->device();
  for (auto v : views_) vkDestroyBufferView(dev, v, nullptr);
  for (auto p : pools_) vkDestroyDescriptorPool(dev, p, nullptr);
  if (pipeline_) vkDestroyPipeline(dev, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(dev, layout_, nullptr);
  if (setLayout_) vkDestroyDescriptorSetLayout(dev, setLayout_, nullptr);
  if (module_) vkDestroyShaderModule(dev, module_, nullptr);
  views_.clear();
  pools_.clear();
  sets_.clear();
  ctx_ = nullptr;
}

Kernel& Kernel::operator=(Kernel&& o) noexcept {
  if (this != &o) {
    destroy();
    ctx_ = std::exchange(o.ctx_, nullptr);
    desc_ = std::move(o.desc_);
    module_ = std::exchange(o.module_, VK_NULL_HANDLE);
    setLayout_ = std::exchange(o.setLayout_, VK_NULL_HANDLE);
    layout_ = std::exchange(o.layout_, VK_NULL_HANDLE);
    pipeline_ = std::exchange(o.pipeline_, VK_NULL_HANDLE);
    pools_ = std::move(o.pools_);
    setsInLastPool_ = o.setsInLastPool_;
    views_ = std::move(o.views_);
    sets_ = std::move(o.sets_);
  }
  return *this;
}

VkDescriptorSet Kernel::descriptorSet(std::span<const BufferRange> bindings) {
  if (bindings.size() != desc_.bindings.size())
    throw Error("kernel " + desc_.shader + " takes " + std::to_string(desc_.bindings.size()) + " buffers, got " +
                std::to_string(bindings.size()));
  std::vector<uint64_t> key;
  for (auto& b : bindings) key.insert(key.end(), {b.buffer->id(), b.offset, b.range});
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
  ai.pSetLayouts = &setLayout_;
  VkDescriptorSet set;
  check(vkAllocateDescriptorSets(dev, &ai, &set), "vkAllocateDescriptorSets");
  ++setsInLastPool_;

  const auto& limits = ctx_->properties().limits;
  std::vector<VkDescriptorBufferInfo> infos(bindings.size());
  std::vector<VkBufferView> views(bindings.size(), VK_NULL_HANDLE);
  std::vector<VkWriteDescriptorSet> writes(bindings.size());
  for (size_t i = 0; i < bindings.size(); ++i) {
    const BufferRange& b = bindings[i];
    VkDeviceSize range = b.range == VK_WHOLE_SIZE ? b.buffer->size() - b.offset : b.range;
    range = std::max<VkDeviceSize>(range, 16);  // empty arrays bind a valid minimal range
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = uint32_t(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = descriptorType(desc_.bindings[i]);
    if (desc_.bindings[i] == Binding::Storage) {
      if (range > limits.maxStorageBufferRange)
        throw Error("kernel " + desc_.shader + ": binding " + std::to_string(i) + " spans " + std::to_string(range) +
                    " bytes, over maxStorageBufferRange " + std::to_string(limits.maxStorageBufferRange) + "; split the batch");
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
        throw Error("kernel " + desc_.shader + ": texel binding " + std::to_string(i) + " holds " + std::to_string(texels) +
                    " texels, over maxTexelBufferElements; split the batch");
      check(vkCreateBufferView(dev, &vi, nullptr, &views[i]), "vkCreateBufferView");
      views_.push_back(views[i]);
      writes[i].pTexelBufferView = &views[i];
    }
  }
  vkUpdateDescriptorSets(dev, uint32_t(writes.size()), writes.data(), 0, nullptr);
  sets_.emplace(std::move(key), set);
  return set;
}

}  // namespace vknerf::gpu

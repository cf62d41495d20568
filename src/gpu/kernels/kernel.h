#pragma once
// A compute pipeline built from an embedded shader, with its descriptor layout, push constants and
// specialization constants. Descriptor sets are created once per distinct set of bound buffers and
// reused, so recording a training step allocates nothing after the first time.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <initializer_list>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/shader_code.h"
#include "gpu/kernels/shader_ids.h"
#include "vknerf/context.h"

namespace vknerf::gpu {

enum class Binding {
  Storage,       // GLSL: layout(std430) buffer
  TexelRgba32f,  // GLSL: layout(rgba32f) uniform readonly imageBuffer (vectorised loads on lavapipe)
  StorageImage,  // GLSL: layout(<format>) uniform writeonly image2D; a caller's view (transientSet only)
};

// The value of the shader's `layout(constant_id = id)` constant (floats by bit pattern). The ids are
// named in the kernel's shaders/<stage>/<kernel>_shared.h, which the shader declares them from:
// {glsl::MlpDenseSpec::KA4, 16}. A constant left out keeps the shader's default.
struct SpecConstant {
  uint32_t id;
  uint32_t value;
};

struct KernelDesc {
  ShaderCode shader;                          // gpu::shaders::<name of shaders/<stage>/<name>.comp>
  std::vector<Binding> bindings;              // binding i of set 0
  uint32_t pushConstantBytes = 0;             // sizeof the kernel's glsl::...Push
  std::vector<SpecConstant> specialization;
};

VkDescriptorType descriptorType(Binding b);

// The Vulkan objects of one compute pipeline made from a KernelDesc on any VkDevice: a Kernel's on
// vknerf's device, and a compiling device's (compile_device.h), which must build the very same
// pipeline for the driver to find its code in the shader cache.
struct PipelineObjects {
  VkShaderModule module = VK_NULL_HANDLE;
  VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  // Throws vknerf::Error, having destroyed what it created.
  static PipelineObjects create(VkDevice dev, VkPipelineCache cache, const KernelDesc& desc);
  void destroy(VkDevice dev);
};

class Kernel {
 public:
  Kernel() = default;
  Kernel(Context& ctx, KernelDesc desc);
  ~Kernel();
  Kernel(Kernel&& o) noexcept { *this = std::move(o); }
  Kernel& operator=(Kernel&& o) noexcept;
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;

  VkPipeline pipeline() const { return objects_.pipeline; }
  VkPipelineLayout layout() const { return objects_.layout; }
  const KernelDesc& desc() const { return desc_; }
  // The descriptor set binding exactly these ranges, created on first use. vknerf's own buffers only.
  VkDescriptorSet descriptorSet(std::span<const BufferRange> bindings);

  // A descriptor set for bindings that include a caller's resources (BufferRange::externalBuffer,
  // BufferRange::storageImage), written on every call: such handles cannot key the cache above,
  // since a destroyed handle's value may be reused for a new object. Calls rewrite a ring of
  // kTransientSets sets in turn, so the set returned stays valid until kTransientSets further calls;
  // by then, the commands that bound it must have finished executing (or never be submitted again).
  // Storage buffers and storage images only.
  static constexpr uint32_t kTransientSets = 64;
  VkDescriptorSet transientSet(std::span<const BufferRange> bindings);

 private:
  void destroy();
  Context* ctx_ = nullptr;
  KernelDesc desc_;
  PipelineObjects objects_;
  std::vector<VkDescriptorPool> pools_;
  uint32_t setsInLastPool_ = 0;
  std::vector<VkBufferView> views_;
  std::map<std::vector<uint64_t>, VkDescriptorSet> sets_;
  VkDescriptorPool transientPool_ = VK_NULL_HANDLE;
  std::vector<VkDescriptorSet> transientSets_;  // allocated on first use
  uint32_t nextTransient_ = 0;
};

// Workgroups needed to cover n items with groups of `local`.
inline uint32_t groupsFor(uint64_t n, uint32_t local) { return uint32_t((n + local - 1) / local); }

}  // namespace vknerf::gpu

#pragma once
// The last stage of Model::recordRender: a rendered block of pixels (the pipeline's colour and depth
// per ray) into the embedding application's RenderTarget, a VkBuffer of RGBA32F texels or a storage
// image (shaders/render/write_render_target*.comp).
#include <memory>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "vknerf/camera.h"
#include "vknerf/render_target.h"

namespace vknerf::nerf {

// Throws vknerf::Error with one line naming the field when `target` cannot receive a render of
// `camera` on this device (size, buffer xor image, format, alignment, focal length, ...).
void checkRenderTarget(const Context& ctx, const Camera& camera, const RenderTarget& target);

class RenderTargetWriter {
 public:
  explicit RenderTargetWriter(Context& ctx);
  ~RenderTargetWriter();

  // One recording's binding of the pipeline's per-ray `color` and `depth` and the caller's target
  // (Kernel::transientSet: valid until Kernel::kTransientSets further binds of the same target kind).
  struct Bound {
    gpu::Kernel* kernel;
    VkDescriptorSet set;
    uint32_t width;
    RenderChannel channel;
    float depthScale;
  };
  Bound bind(const RenderTarget& target, const gpu::Buffer& color, const gpu::Buffer& depth);
  // Writes pixels [first, first + count) from rays [0, count) of the last rendered block.
  void record(gpu::Recorder& rec, const Bound& bound, uint32_t first, uint32_t count);

 private:
  gpu::Kernel& kernelFor(const RenderTarget& target);
  Context& ctx_;
  // Created on first use: a model rendered into one kind of target compiles one kernel.
  std::unique_ptr<gpu::Kernel> buffer_, rgba32f_, rgba8_;
};

}  // namespace vknerf::nerf

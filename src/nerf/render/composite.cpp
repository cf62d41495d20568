#include "nerf/render/composite.h"

#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {
constexpr uint32_t kLocal = 64;

gpu::KernelDesc desc(const gpu::ShaderCode& shader, uint32_t pushBytes) {
  using gpu::Binding;
  return {shader,
          {Binding::Storage, Binding::Storage, Binding::TexelRgba32f, Binding::Storage, Binding::Storage,
           Binding::Storage, Binding::Storage},
          pushBytes,
          {}};
}
}  // namespace

Compositor::Compositor(Context& ctx)
    : dummy_(ctx, 16),
      forward_(ctx, desc(gpu::shaders::composite_forward, sizeof(Push))),
      backward_(ctx, desc(gpu::shaders::composite_backward, sizeof(Push))) {}

void Compositor::dispatch(gpu::Recorder& rec, gpu::Kernel& kernel, const char* label, uint32_t numRays,
                          uint32_t samplesPerRay, const gpu::BufferRange& rayOffsets, const gpu::BufferRange& samples,
                          const gpu::BufferRange& field, const std::array<float, 3>& background,
                          const gpu::BufferRange* perRayBackground, const gpu::BufferRange& out0,
                          const gpu::BufferRange& out1, const gpu::BufferRange& out2) {
  if (samplesPerRay == 0 && numRays > 0 && !rayOffsets.buffer)
    throw Error("Compositor: samplesPerRay == 0 (packed layout) needs a rayOffsets buffer");
  Push p{{background[0], background[1], background[2], 0}, numRays, samplesPerRay, perRayBackground ? 1u : 0u, 0};
  gpu::BufferRange offsets = rayOffsets.buffer ? rayOffsets : gpu::BufferRange(dummy_);
  gpu::BufferRange bg = perRayBackground ? *perRayBackground : gpu::BufferRange(dummy_);
  rec.dispatch(kernel, {offsets, samples, field, bg, out0, out1, out2}, p, gpu::groupsFor(numRays, kLocal), 1, 1, label);
}

void Compositor::recordForward(gpu::Recorder& rec, uint32_t numRays, uint32_t samplesPerRay,
                               const gpu::BufferRange& rayOffsets, const gpu::BufferRange& samples,
                               const gpu::BufferRange& field, const std::array<float, 3>& background,
                               const gpu::BufferRange* perRayBackground, const gpu::BufferRange& outColor,
                               const gpu::BufferRange& outDepth, const gpu::BufferRange& outWeights) {
  dispatch(rec, forward_, "composite_forward", numRays, samplesPerRay, rayOffsets, samples, field, background,
           perRayBackground, outColor, outDepth, outWeights);
}

void Compositor::recordBackward(gpu::Recorder& rec, uint32_t numRays, uint32_t samplesPerRay,
                                const gpu::BufferRange& rayOffsets, const gpu::BufferRange& samples,
                                const gpu::BufferRange& field, const std::array<float, 3>& background,
                                const gpu::BufferRange* perRayBackground, const gpu::BufferRange& dColor,
                                const gpu::BufferRange& dDepth, const gpu::BufferRange& dField) {
  dispatch(rec, backward_, "composite_backward", numRays, samplesPerRay, rayOffsets, samples, field, background,
           perRayBackground, dColor, dDepth, dField);
}

}  // namespace vknerf::nerf

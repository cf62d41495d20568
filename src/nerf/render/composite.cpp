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

Compositor::Push Compositor::push(uint32_t numRays, uint32_t samplesPerRay, const gpu::BufferRange& rayOffsets,
                                  const std::array<float, 3>& background,
                                  const gpu::BufferRange* perRayBackground) const {
  if (samplesPerRay == 0 && numRays > 0 && !rayOffsets.buffer)
    throw Error("Compositor: samplesPerRay == 0 (packed layout) needs a rayOffsets buffer");
  return {{background[0], background[1], background[2], 0}, numRays, samplesPerRay, perRayBackground ? 1u : 0u, 0};
}

void Compositor::recordForward(gpu::Recorder& rec, uint32_t numRays, uint32_t samplesPerRay,
                               const gpu::BufferRange& rayOffsets, const gpu::BufferRange& samples,
                               const gpu::BufferRange& field, const std::array<float, 3>& background,
                               const gpu::BufferRange* perRayBackground, const gpu::BufferRange& outColor,
                               const gpu::BufferRange& outDepth, const gpu::BufferRange& outWeights) {
  Push p = push(numRays, samplesPerRay, rayOffsets, background, perRayBackground);
  gpu::BufferRange offsets = rayOffsets.buffer ? rayOffsets : gpu::BufferRange(dummy_);
  gpu::BufferRange bg = perRayBackground ? *perRayBackground : gpu::BufferRange(dummy_);
  rec.dispatch(forward_, {offsets, samples, field, bg, outColor, outDepth, outWeights}, p,
               gpu::groupsFor(numRays, kLocal), 1, 1, "composite_forward");
}

void Compositor::recordBackward(gpu::Recorder& rec, uint32_t numRays, uint32_t samplesPerRay,
                                const gpu::BufferRange& rayOffsets, const gpu::BufferRange& samples,
                                const gpu::BufferRange& field, const std::array<float, 3>& background,
                                const gpu::BufferRange* perRayBackground, const gpu::BufferRange& dColor,
                                const gpu::BufferRange& dDepth, const gpu::BufferRange& dField) {
  Push p = push(numRays, samplesPerRay, rayOffsets, background, perRayBackground);
  gpu::BufferRange offsets = rayOffsets.buffer ? rayOffsets : gpu::BufferRange(dummy_);
  gpu::BufferRange bg = perRayBackground ? *perRayBackground : gpu::BufferRange(dummy_);
  rec.dispatch(backward_, {offsets, samples, field, bg, dColor, dDepth, dField}, p, gpu::groupsFor(numRays, kLocal),
               1, 1, "composite_backward");
}

}  // namespace vknerf::nerf

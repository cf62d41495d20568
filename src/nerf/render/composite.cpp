#include "nerf/render/composite.h"

#include <cmath>
#include <string>

#include "gpu/buffer.h"
#include "nerf/rays/rays.h"
#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {
constexpr uint32_t kLocal = 64;

gpu::KernelDesc desc(const gpu::ShaderCode& shader, uint32_t pushBytes) {
  using gpu::Binding;
  return {shader,
          {Binding::Storage, Binding::Storage, Binding::TexelRgba32f, Binding::Storage, Binding::Storage,
           Binding::Storage, Binding::Storage, Binding::Storage, Binding::Storage},
          pushBytes,
          {}};
}
}  // namespace

Compositor::Compositor(Context& ctx)
    : dummy_(ctx, 16),
      forward_(ctx, desc(gpu::shaders::composite_forward, sizeof(Push))),
      backward_(ctx, desc(gpu::shaders::composite_backward, sizeof(Push))) {}

float Compositor::maxOpticalDepth(float minTransmittance) {
  if (!(minTransmittance > 0.0f && minTransmittance <= 1.0f))
    throw Error("Compositor: minTransmittance " + std::to_string(minTransmittance) + " is outside (0, 1]");
  return float(-std::log(double(minTransmittance)));
}

void Compositor::dispatch(gpu::Recorder& rec, gpu::Kernel& kernel, const char* label, uint32_t numRays,
                          uint32_t samplesPerRay, const gpu::BufferRange& rayOffsets, const gpu::BufferRange& samples,
                          const gpu::BufferRange& field, const std::array<float, 3>& background,
                          const gpu::BufferRange* perRayBackground, const gpu::BufferRange& out0,
                          const gpu::BufferRange& out1, const gpu::BufferRange& out2, float maxOpticalDepth,
                          const gpu::BufferRange* out3, const DistortionLoss* distortion) {
  if (samplesPerRay == 0 && numRays > 0 && !rayOffsets.buffer)
    throw Error("Compositor: samplesPerRay == 0 (packed layout) needs a rayOffsets buffer");
  if (!(maxOpticalDepth >= 0.0f)) throw Error("Compositor: maxOpticalDepth must be >= 0 (or +inf)");
  const bool distorted = distortion && distortion->weight != 0.0f;
  if (distortion) {
    const DistortionLoss& d = *distortion;
    if (!(d.weight >= 0.0f && std::isfinite(d.weight)))
      throw Error("Compositor: the distortion loss weight must be finite and >= 0, got " + std::to_string(d.weight));
    if (!(d.dtMin > 0.0f && d.dtMax >= d.dtMin && std::isfinite(d.dtMax) && d.coneAngle >= 0.0f && std::isfinite(d.coneAngle)))
      throw Error("Compositor: the distortion loss's march spacing needs 0 < dtMin <= dtMax and a cone angle >= 0");
    if (distorted) gpu::requireBytes("Compositor", "rays", d.rays, uint64_t(numRays) * kRayBytes);
  }
  if (out3) gpu::requireBytes("Compositor", "keptCounts", *out3, uint64_t(numRays) * 4);
  Push p{{background[0], background[1], background[2], 0}, numRays, samplesPerRay, perRayBackground ? 1u : 0u,
         maxOpticalDepth, out3 ? 1u : 0u, distorted ? distortion->weight : 0.0f,
         distorted ? distortion->coneAngle : 0.0f, distorted ? distortion->dtMin : 1.0f,
         distorted ? distortion->dtMax : 1.0f};
  gpu::BufferRange offsets = rayOffsets.buffer ? rayOffsets : gpu::BufferRange(dummy_);
  gpu::BufferRange bg = perRayBackground ? *perRayBackground : gpu::BufferRange(dummy_);
  gpu::BufferRange kept = out3 ? *out3 : gpu::BufferRange(dummy_);
  gpu::BufferRange rays = distorted ? distortion->rays : gpu::BufferRange(dummy_);
  rec.dispatch(kernel, {offsets, samples, field, bg, out0, out1, out2, kept, rays}, p, gpu::groupsFor(numRays, kLocal),
               1, 1, label);
}

void Compositor::recordForward(gpu::Recorder& rec, uint32_t numRays, uint32_t samplesPerRay,
                               const gpu::BufferRange& rayOffsets, const gpu::BufferRange& samples,
                               const gpu::BufferRange& field, const std::array<float, 3>& background,
                               const gpu::BufferRange* perRayBackground, const gpu::BufferRange& outColor,
                               const gpu::BufferRange& outDepth, const gpu::BufferRange& outWeights,
                               float maxOpticalDepth, const gpu::BufferRange* outKeptCounts) {
  dispatch(rec, forward_, "composite_forward", numRays, samplesPerRay, rayOffsets, samples, field, background,
           perRayBackground, outColor, outDepth, outWeights, maxOpticalDepth, outKeptCounts, nullptr);
}

void Compositor::recordBackward(gpu::Recorder& rec, uint32_t numRays, uint32_t samplesPerRay,
                                const gpu::BufferRange& rayOffsets, const gpu::BufferRange& samples,
                                const gpu::BufferRange& field, const std::array<float, 3>& background,
                                const gpu::BufferRange* perRayBackground, const gpu::BufferRange& dColor,
                                const gpu::BufferRange& dDepth, const gpu::BufferRange& dField,
                                float maxOpticalDepth, const DistortionLoss* distortion) {
  dispatch(rec, backward_, "composite_backward", numRays, samplesPerRay, rayOffsets, samples, field, background,
           perRayBackground, dColor, dDepth, dField, maxOpticalDepth, nullptr, distortion);
}

}  // namespace vknerf::nerf

#include "nerf/render/composite.h"

#include <cmath>
#include <string>

#include "gpu/memory/buffer.h"
#include "nerf/rays/rays.h"
#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {
constexpr uint32_t kLocal = 64;

gpu::KernelDesc desc(const gpu::ShaderCode& shader, uint32_t pushBytes) {
  using gpu::Binding;
  return {shader,
          {Binding::Storage, Binding::Storage, Binding::TexelRgba32f, Binding::Storage, Binding::Storage,
           Binding::Storage, Binding::Storage, Binding::Storage, Binding::Storage, Binding::Storage},
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

void Compositor::dispatch(gpu::Recorder& rec, gpu::Kernel& kernel, const char* label, const CompositeInputs& in,
                          const Outputs& out, const std::optional<DistortionLoss>& distortion,
                          const std::optional<gpu::BufferRange>& termValues) {
  const uint32_t numRays = in.numRays, samplesPerRay = in.samplesPerRay;
  const float maxOpticalDepth = in.maxOpticalDepth;
  const std::array<float, 3>& background = in.background;
  const gpu::BufferRange* perRayBackground = in.perRayBackground ? &*in.perRayBackground : nullptr;
  const gpu::BufferRange* out3 = out.out3 ? &*out.out3 : nullptr;
  const gpu::BufferRange& rayOffsets = in.rayOffsets;
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
  if (termValues) gpu::requireBytes("Compositor", "termValues", *termValues, uint64_t(numRays) * 4 * kRayLossColumns);
  Push p{{background[0], background[1], background[2], 0}, numRays, samplesPerRay, perRayBackground ? 1u : 0u,
         maxOpticalDepth, out3 ? 1u : 0u, distorted ? distortion->weight : 0.0f,
         distorted ? distortion->coneAngle : 0.0f, distorted ? distortion->dtMin : 1.0f,
         distorted ? distortion->dtMax : 1.0f, termValues ? 1u : 0u,
         distorted && distortion->farField ? 1u : 0u};
  gpu::BufferRange offsets = rayOffsets.buffer ? rayOffsets : gpu::BufferRange(dummy_);
  gpu::BufferRange bg = perRayBackground ? *perRayBackground : gpu::BufferRange(dummy_);
  gpu::BufferRange kept = out3 ? *out3 : gpu::BufferRange(dummy_);
  gpu::BufferRange rays = distorted ? distortion->rays : gpu::BufferRange(dummy_);
  gpu::BufferRange values = termValues ? *termValues : gpu::BufferRange(dummy_);
  rec.dispatch(kernel, {offsets, in.samples, in.field, bg, out.out0, out.out1, out.out2, kept, rays, values}, p,
               gpu::groupsFor(numRays, kLocal), 1, 1, label);
}

void Compositor::recordForward(gpu::Recorder& rec, const CompositeInputs& in, const CompositeOutputs& out) {
  dispatch(rec, forward_, "composite_forward", in, {out.color, out.depth, out.weights, out.keptCounts}, std::nullopt,
           std::nullopt);
}

void Compositor::recordBackward(gpu::Recorder& rec, const CompositeInputs& in, const CompositeGradients& grads) {
  std::optional<DistortionLoss> distortion;
  for (const RayLossTerm& term : grads.terms) {
    if (const auto* d = std::get_if<DistortionLoss>(&term)) {
      if (distortion) throw Error("Compositor: the distortion loss is listed twice");
      distortion = *d;
    }
  }
  dispatch(rec, backward_, "composite_backward", in, {grads.dColor, grads.dDepth, grads.dField, std::nullopt},
           distortion, grads.termValues);
}

}  // namespace vknerf::nerf

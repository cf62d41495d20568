#pragma once
// Volume-rendering compositing (shaders/render/composite_forward.comp, composite_backward.comp).
// Layouts, all tightly packed:
//   samples     vec2 (t, delta) per sample
//   field       vec4 (r, g, b, sigma) per sample, sigma activated (>= 0, may be +inf); bound as an
//               rgba32f texel buffer, so its offset must be a multiple of 16 bytes
//   rayOffsets  uint[numRays + 1], used only when samplesPerRay == 0 (packed layout): ray r owns
//               samples [off[r], off[r+1]); with samplesPerRay = N > 0 ray r owns [r*N, (r+1)*N)
//   background  vec4 (r, g, b, unused) per ray when perRayBackground is given
//   color       vec4 (r, g, b, opacity) per ray, C = sum w_i c_i + T_final * bg, opacity = 1 - T_final
//   depth       float per ray, sum w_i t_i (not normalised)
//   weights     float per sample, w_i = T_i * alpha_i
//   dColor      vec4 dL/d(r, g, b, opacity) per ray; dDepth float dL/ddepth per ray
//   dField      vec4 dL/d(r, g, b, sigma) per sample
//   keptCounts  uint per ray: the samples it composited (early termination)
// Early termination (instant-ngp's): with a finite maxOpticalDepth a ray stops once the optical
// depth in front of its next sample exceeds it (transmittance below exp(-maxOpticalDepth)); the
// sample that crosses it is kept (tests/reference keptSamples). Both passes make the same decision;
// the samples behind the cut get weight 0 and gradient 0, and the kept ones exactly what a batch
// holding only them would get. The light they could add is below that transmittance times their
// brightest colour. The backward, the expensive part, skips them: the fast model's runs over the
// kept samples alone (nerf::KeptRows), a backward over every sample gets zeros from them.
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <variant>
#include <vector>

#include "nerf/sampling/packed_samples.h"
#include "nerf/sampling/sample_layout.h"
#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "render/composite_shared.h"

namespace vknerf::nerf {

constexpr VkDeviceSize kFieldBytes = 16;
constexpr VkDeviceSize kColorBytes = 16;  // a ray's colour (and its gradient, its background): vec4
constexpr VkDeviceSize kDepthBytes = 4;   // a ray's depth: float

// The distortion loss the backward pass adds (mip-NeRF 360's; tests/reference/render/distortion_loss.h):
// its weight per ray, and what it measures distances in: the march's spacing and each ray's near
// and far, read from the rays (nerf::kRayBytes each: (o, t_near), (d, t_far)).
struct DistortionLoss {
  float weight = 0;
  float coneAngle = 0, dtMin = 1, dtMax = 1;  // step(t) = clamp(t coneAngle, dtMin, dtMax)
  gpu::BufferRange rays;
  // The weight a ray leaves to what lies behind the box counts as one more interval at its far end
  // (ref::DistortionRay::farField), so that handing weight to the far field is not free.
  bool farField = false;
};

// What both passes read, built once for a batch and handed to its forward and then its backward:
// numRays rays' samples, the field at them, what lies behind each ray and where it stops.
struct CompositeInputs {
  uint32_t numRays = 0;
  uint32_t samplesPerRay = 0;   // N > 0: ray r owns samples [r*N, (r+1)*N); 0: the packed layout
  gpu::BufferRange rayOffsets;  // the packed layout's offsets; unused (may stay empty) when N > 0
  gpu::BufferRange samples, field;
  std::array<float, 3> background = {0, 0, 0};       // behind every ray, unless perRayBackground
  std::optional<gpu::BufferRange> perRayBackground;  // behind each ray
  float maxOpticalDepth = std::numeric_limits<float>::infinity();  // early termination (none: +inf)

  // The first numRays rays of a packed batch (samplesPerRay = 0).
  static CompositeInputs packed(uint32_t numRays, const PackedSamples& batch, const gpu::BufferRange& field) {
    CompositeInputs in;
    in.numRays = numRays;
    in.rayOffsets = batch.offsets;
    in.samples = batch.samples;
    in.field = field;
    return in;
  }
};

// What the forward writes; keptCounts (early termination) is optional.
struct CompositeOutputs {
  gpu::BufferRange color, depth, weights;
  std::optional<gpu::BufferRange> keptCounts;
};

// The loss terms the backward pass adds per ray to the loss whose colour gradient dColor carries:
// one list, each kind at most once, each with its weight. A term's column is where each ray's
// weighted value of it goes in CompositeGradients::termValues (the loss's report). A new per-ray
// term is an alternative here, a column and a block of shaders/render/composite_backward.comp.
using RayLossTerm = std::variant<DistortionLoss>;
constexpr uint32_t kRayLossColumns = 4;  // termValues holds a vec4 per ray
inline uint32_t rayLossColumn(const RayLossTerm& term) { return uint32_t(term.index()); }

// What the backward reads (dColor, dDepth) and writes (dField, in full); `terms` adds each term's
// weight times its value per ray (the distortion loss: ref::distortionLoss) to the loss, and,
// with termValues (vec4 per ray), writes those weighted values in the terms' columns.
struct CompositeGradients {
  gpu::BufferRange dColor, dDepth, dField;
  std::vector<RayLossTerm> terms;
  std::optional<gpu::BufferRange> termValues;
};

class Compositor {
 public:
  explicit Compositor(Context& ctx);

  static constexpr float kNoTermination = std::numeric_limits<float>::infinity();
  // The optical depth the kernels compare against: -ln(minTransmittance), rounded to float.
  static float maxOpticalDepth(float minTransmittance);

  void recordForward(gpu::Recorder& rec, const CompositeInputs& in, const CompositeOutputs& out);
  // Recomputes T and w from the inputs rather than reading the forward outputs: the stable
  // back-to-front suffix sums need only the field.
  void recordBackward(gpu::Recorder& rec, const CompositeInputs& in, const CompositeGradients& grads);

 private:
  using Push = glsl::CompositePush;
  // Both passes bind the same inputs and four outputs (forward: colour, depth, weights, kept
  // counts; backward: dColor, dDepth, dField, nothing), then the rays (backward's distortion loss)
  // and the terms' values (backward).
  struct Outputs {
    gpu::BufferRange out0, out1, out2;
    std::optional<gpu::BufferRange> out3;
  };
  void dispatch(gpu::Recorder& rec, gpu::Kernel& kernel, const char* label, const CompositeInputs& in,
                const Outputs& out, const std::optional<DistortionLoss>& distortion,
                const std::optional<gpu::BufferRange>& termValues);

  gpu::Buffer dummy_;  // bound where the layout or the background source leaves a binding unused
  gpu::Kernel forward_, backward_;
};

}  // namespace vknerf::nerf

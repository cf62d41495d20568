#pragma once
// The proposal estimator's training signal (shaders/sampling/proposal_interlevel.comp; mip-NeRF 360's
// interlevel loss, eq. 13): the field's weights on the samples the proposal placed should be bounded
// by the proposal's weights on the candidates that overlap them, L = weight * sum_j max(0, w_j -
// B_j)^2 / (w_j + epsilon) per ray. Writes each ray's loss, dL/d(proposal weight) and the proposal
// field's gradient (0, 0, 0, dL/dsigma) per candidate; the field's weights are constants (only the
// proposal learns from it).
#include <cstdint>

#include "nerf/sampling/packed_samples.h"
#include "nerf/sampling/proposal_batch.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"

namespace vknerf::nerf {

class InterlevelLoss {
 public:
  explicit InterlevelLoss(Context& ctx);

  struct Terms {
    float weight = 1.0f;
    float epsilon = 1e-7f;  // nerfacto's: float's machine epsilon
  };
  // Per candidate: dWeights (float) and dField (vec4); per ray: rayLoss (float).
  struct Gradients {
    gpu::BufferRange dWeights, dField, rayLoss;
  };
  // `samples`: the offsets and samples the proposal placed; `fieldWeights`: the field's compositing
  // weight of each (float per sample).
  // Throws vknerf::Error for a weight or epsilon that is negative or not finite, or offsets and
  // per-ray outputs too small for numRays.
  void record(gpu::Recorder& rec, uint32_t numRays, const ProposalCandidates& candidates,
              const PackedSamples& samples, const gpu::BufferRange& fieldWeights, const Terms& terms,
              const Gradients& out);

 private:
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

#pragma once
// The proposal estimator's sampling (shaders/sampling/proposal_sample.comp; nerfacto's proposal
// sampler): each ray's samples placed by inverse CDF of the proposal's weights on its candidates,
// measured in occupied length (the march's gaps cost nothing). Ray r gets as many samples as its
// sample offsets give it (offsets[r+1] - offsets[r]); a ray without occupied length gets samples
// (0, 0), which weigh nothing.
#include <cstdint>

#include "nerf/sampling/proposal_batch.h"
#include "nerf/sampling/samplers.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"

namespace vknerf::nerf {

class ProposalSampler {
 public:
  explicit ProposalSampler(Context& ctx);

  // How the samples are drawn: one random shift of the edge quantiles a ray, keyed by (seed, ray)
  // (jitter, in training) or none, and the uniform share `padding` in [0, 1] of the sampling mass,
  // spread over the occupied length. Throws vknerf::Error for a padding outside [0, 1] or offsets
  // too small for numRays.
  struct Draws {
    Jitter jitter;
    float padding = 0.01f;
  };
  void record(gpu::Recorder& rec, uint32_t numRays, const ProposalCandidates& candidates, const Draws& draws,
              const ProposalSamples& out);

 private:
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

#include "nerf/sampling/proposal_sampler.h"

#include <cmath>
#include <string>

#include "vknerf/error.h"
#include "sampling/proposal_sample_shared.h"
#include "sampling/sampling_shared.h"

namespace vknerf::nerf {
namespace {

// One invocation per ray, as sample_pdf: small groups so that a few thousand rays still spread
// over lavapipe's worker threads.
constexpr uint32_t kLocal = 32;

}  // namespace

ProposalSampler::ProposalSampler(Context& ctx)
    : kernel_(ctx, {gpu::shaders::proposal_sample,
                    {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                     gpu::Binding::Storage},
                    sizeof(glsl::ProposalSamplePush),
                    {{glsl::SamplingSpec::LOCAL_SIZE_X, kLocal}}}) {}

void ProposalSampler::record(gpu::Recorder& rec, uint32_t numRays, const ProposalCandidates& candidates,
                             const Draws& draws, const ProposalSamples& out) {
  if (!(draws.padding >= 0.0f && draws.padding <= 1.0f))
    throw Error("proposal_sample: padding " + std::to_string(draws.padding) + " must be in [0, 1]");
  const uint64_t offsetBytes = (uint64_t(numRays) + 1) * sizeof(uint32_t);
  gpu::requireBytes("proposal_sample", "candidate offsets", candidates.offsets, offsetBytes);
  gpu::requireBytes("proposal_sample", "sample offsets", out.offsets, offsetBytes);
  glsl::ProposalSamplePush p{numRays, draws.jitter.seed, draws.jitter.jitter ? 1u : 0u, draws.padding};
  rec.dispatchFlat(kernel_, {candidates.offsets, candidates.samples, candidates.sigma, out.offsets, out.samples}, p,
                   numRays, kLocal, "proposal_sample");
}

}  // namespace vknerf::nerf

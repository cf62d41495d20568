#include "nerf/sampling/interlevel_loss.h"

#include <cmath>
#include <string>

#include "vknerf/error.h"
#include "sampling/proposal_interlevel_shared.h"
#include "sampling/sampling_shared.h"

namespace vknerf::nerf {
namespace {

constexpr uint32_t kLocal = 32;  // one invocation per ray, as ProposalSampler

}  // namespace

InterlevelLoss::InterlevelLoss(Context& ctx)
    : kernel_(ctx, {gpu::shaders::proposal_interlevel,
                    std::vector<gpu::Binding>(9, gpu::Binding::Storage),
                    sizeof(glsl::InterlevelPush),
                    {{glsl::SamplingSpec::LOCAL_SIZE_X, kLocal}}}) {}

void InterlevelLoss::record(gpu::Recorder& rec, uint32_t numRays, const ProposalCandidates& candidates,
                            const PackedSamples& samples, const gpu::BufferRange& fieldWeights,
                            const Terms& terms, const Gradients& out) {
  if (!(std::isfinite(terms.weight) && terms.weight >= 0.0f))
    throw Error("proposal_interlevel: weight " + std::to_string(terms.weight) + " must be finite and >= 0");
  if (!(std::isfinite(terms.epsilon) && terms.epsilon > 0.0f))
    throw Error("proposal_interlevel: epsilon " + std::to_string(terms.epsilon) + " must be finite and > 0");
  const uint64_t offsetBytes = (uint64_t(numRays) + 1) * sizeof(uint32_t);
  gpu::requireBytes("proposal_interlevel", "candidate offsets", candidates.offsets, offsetBytes);
  gpu::requireBytes("proposal_interlevel", "sample offsets", samples.offsets, offsetBytes);
  gpu::requireBytes("proposal_interlevel", "ray losses", out.rayLoss, uint64_t(numRays) * sizeof(float));
  if (numRays == 0) return;
  glsl::InterlevelPush p{numRays, terms.weight, terms.epsilon};
  rec.dispatchFlat(kernel_,
                   {candidates.offsets, candidates.samples, candidates.field, samples.offsets, samples.samples,
                    fieldWeights, out.dWeights, out.dField, out.rayLoss},
                   p, numRays, kLocal, "proposal_interlevel");
}

}  // namespace vknerf::nerf

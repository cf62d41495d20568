#include "nerf/sampling/proposal_sampler.h"

#include <string>

#include "nerf/rays/rays.h"
#include "vknerf/error.h"
#include "sampling/proposal_count_shared.h"
#include "sampling/proposal_sample_shared.h"
#include "sampling/sampling_shared.h"

namespace vknerf::nerf {
namespace {

// One invocation per ray, as sample_pdf: small groups so that a few thousand rays still spread
// over lavapipe's worker threads.
constexpr uint32_t kLocal = 32;

// A draw's share in [0, 1] (NaN refused), named in the error.
void requireUnitShare(const char* name, float value) {
  if (!(value >= 0.0f && value <= 1.0f))
    throw Error(std::string("proposal_sample: ") + name + " " + std::to_string(value) + " must be in [0, 1]");
}

}  // namespace

ProposalSampler::ProposalSampler(Context& ctx, uint32_t maxRays)
    : maxRays_(maxRays),
      layout_(ctx, maxRays),
      count_(ctx, {gpu::shaders::proposal_count, {gpu::Binding::Storage, gpu::Binding::Storage},
                   sizeof(glsl::ProposalCountPush), {{glsl::SamplingSpec::LOCAL_SIZE_X, kLocal}}}),
      sample_(ctx, {gpu::shaders::proposal_sample, std::vector<gpu::Binding>(9, gpu::Binding::Storage),
                    sizeof(glsl::ProposalSamplePush), {{glsl::SamplingSpec::LOCAL_SIZE_X, kLocal}}}) {}

void ProposalSampler::record(gpu::Recorder& rec, uint32_t numRays, const ProposalCandidates& candidates,
                             const Draws& draws, uint32_t capacity, const PackedSamples& out,
                             const std::optional<FieldInputs>& points) {
  if (numRays > maxRays_)
    throw Error("proposal_sample: " + std::to_string(numRays) + " rays over the sampler's " + std::to_string(maxRays_));
  if (draws.samplesPerRay == 0) throw Error("proposal_sample: samples per ray must be at least 1");
  if (draws.candidateSpan == 0)
    throw Error("proposal_sample: a candidate must stand for at least 1 march step");
  requireUnitShare("padding", draws.padding);
  requireUnitShare("anneal", draws.anneal);
  gpu::requireBytes("proposal_sample", "candidate offsets", candidates.offsets, (uint64_t(numRays) + 1) * sizeof(uint32_t));
  PackedLayout::requireOutputs("proposal_sample", numRays, out.offsets, out.totals);
  gpu::requireBytes("proposal_sample", "samples", out.samples, uint64_t(capacity) * kSampleBytes);
  gpu::requireBytes("proposal_sample", "sample rays", out.sampleRay, uint64_t(capacity) * sizeof(uint32_t));
  if (points) {
    requireBoxNotEmpty("proposal_sample", points->box);
    gpu::requireBytes("proposal_sample", "rays", points->rays, uint64_t(numRays) * kRayBytes);
    gpu::requireBytes("proposal_sample", "positions", points->out.positions, uint64_t(capacity) * 16);
    gpu::requireBytes("proposal_sample", "directions", points->out.directions, uint64_t(capacity) * 16);
  }
  if (numRays == 0) return;
  const glsl::ProposalCountPush count{numRays, draws.samplesPerRay, draws.candidateSpan};
  rec.dispatchFlat(count_, {candidates.offsets, layout_.counts()}, count, numRays, kLocal, "proposal_count");
  layout_.recordOffsetsAndTotals(rec, numRays, capacity, out.offsets, out.totals);
  glsl::ProposalSamplePush p{{0, 0, 0, 0}, {1, 1, 1, 0}, numRays, draws.jitter.seed, draws.jitter.jitter ? 1u : 0u,
                             draws.padding, draws.anneal, points ? 1u : 0u};
  if (points)
    for (int k = 0; k < 3; ++k) p.boxMin[k] = points->box.min[k], p.boxMax[k] = points->box.max[k];
  // Without points their bindings are never touched: the samples stand in for them.
  const gpu::BufferRange &rays = points ? points->rays : out.samples,
                         &positions = points ? points->out.positions : out.samples,
                         &directions = points ? points->out.directions : out.samples;
  rec.dispatchFlat(sample_,
                   {candidates.offsets, candidates.samples, candidates.field, out.offsets, out.samples, out.sampleRay,
                    rays, positions, directions},
                   p, numRays, kLocal, "proposal_sample");
}

}  // namespace vknerf::nerf

#pragma once
// The proposal estimator's sampling (shaders/sampling/proposal_count.comp, proposal_sample.comp;
// nerfacto's proposal sampler): each ray's samples placed by inverse CDF of the proposal's weights
// on its candidates, measured in occupied length (the march's gaps cost nothing), into a packed
// batch (nerf::PackedSamples): samplesPerRay for every ray with candidates (at most the march steps
// they stand for), none for the others,
// the offsets clamped at the output's capacity as a march's are (a ray cut there gets fewer
// samples, spread over its whole occupied length). A sample is (t, delta), delta its bin's length.
#include <cstdint>
#include <optional>

#include "nerf/sampling/packed_layout.h"
#include "nerf/sampling/packed_samples.h"
#include "nerf/sampling/point_buffers.h"
#include "nerf/sampling/proposal_batch.h"
#include "nerf/sampling/samplers.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

class ProposalSampler {
 public:
  ProposalSampler(Context& ctx, uint32_t maxRays);

  // How the samples are drawn: samplesPerRay of them, one random shift of the edge quantiles a
  // ray keyed by (seed, ray) (jitter, in training) or none, and the uniform share `padding` in
  // [0, 1] of the sampling mass, spread over the occupied length; anneal a in [0, 1]: a weight w
  // enters the mass as w^a (its candidate's share of the occupied length)^(1 - a), uniform by
  // length at 0 (nerfacto anneals its proposal's weights so over its first steps). candidateSpan:
  // the most march steps one candidate stands for (the march's stretch, 1 without): a ray of k
  // candidates gets min(samplesPerRay, k candidateSpan) samples, never more than the march's.
  struct Draws {
    uint32_t samplesPerRay = 0;
    Jitter jitter;
    float padding = 0.01f;
    float anneal = 1.0f;
    uint32_t candidateSpan = 1;
  };
  // The samples' field inputs, written by the same pass (what PackedSamplePoints would make of
  // them, bit for bit, without another pass over the batch): `rays` the rays sampled (sampleRay
  // indexes them), `box` the scene box the positions are mapped from, `out` vec4 per sample.
  struct FieldInputs {
    gpu::BufferRange rays;
    Aabb box;
    PointBuffers out;
  };
  // `capacity`: the samples out.samples and out.sampleRay (and points' outputs) hold. Throws
  // vknerf::Error for more than maxRays rays, no samples a ray, a candidate span of 0, a padding
  // or anneal outside [0, 1], an empty box, or buffers too small for the rays or the capacity.
  void record(gpu::Recorder& rec, uint32_t numRays, const ProposalCandidates& candidates, const Draws& draws,
              uint32_t capacity, const PackedSamples& out, const std::optional<FieldInputs>& points = std::nullopt);

 private:
  uint32_t maxRays_;
  PackedLayout layout_;
  gpu::Kernel count_, sample_;
};

}  // namespace vknerf::nerf

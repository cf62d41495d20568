#version 450
// The proposal estimator's samples per ray (nerf::ProposalSampler; ref::proposalCount): samplesPerRay
// for a ray with candidates, but never more than the march steps they stand for (k candidates of
// up to candidateSpan steps each), and none for a ray the march found empty: a ray that crosses
// little occupied space costs the field no more than the march would, one that misses everything
// nothing. PackedLayout turns the counts into offsets and totals.
#extension GL_GOOGLE_include_directive : require
#include "sampling/sampling.glsl"

layout(std430, binding = 0) readonly buffer CandidateOffsets { uint candidateOffsets[]; };  // numRays + 1
layout(std430, binding = 1) writeonly buffer Counts { uint counts[]; };                     // per ray

#include "sampling/proposal_count_shared.h"

void main() {
  uint ray = flatInvocation();
  if (ray >= pc.numRays) return;
  uint k = candidateOffsets[ray + 1u] - candidateOffsets[ray];
  // min(samplesPerRay, k candidateSpan) without the product overflowing.
  bool enough = k >= (pc.samplesPerRay + pc.candidateSpan - 1u) / pc.candidateSpan;
  counts[ray] = enough ? pc.samplesPerRay : k * pc.candidateSpan;
}

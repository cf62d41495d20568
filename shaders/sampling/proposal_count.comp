#version 450
// The proposal estimator's samples per ray (nerf::ProposalSampler): samplesPerRay for a ray with
// candidates, none for a ray the march found empty, so that a ray that misses everything costs
// the field nothing. PackedLayout turns the counts into offsets and totals.
#extension GL_GOOGLE_include_directive : require
#include "sampling/sampling.glsl"

layout(std430, binding = 0) readonly buffer CandidateOffsets { uint candidateOffsets[]; };  // numRays + 1
layout(std430, binding = 1) writeonly buffer Counts { uint counts[]; };                     // per ray

#include "sampling/proposal_count_shared.h"

void main() {
  uint ray = flatInvocation();
  if (ray >= pc.numRays) return;
  counts[ray] = candidateOffsets[ray + 1u] > candidateOffsets[ray] ? pc.samplesPerRay : 0u;
}

// The push constants of proposal_sample.comp; on the host, vknerf::glsl::ProposalSamplePush.
#ifndef VKNERF_SAMPLING_PROPOSAL_SAMPLE_SHARED_H
#define VKNERF_SAMPLING_PROPOSAL_SAMPLE_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(ProposalSamplePush)
  vec4 boxMin;    // points: the scene box the positions are mapped from
  vec4 boxMax;
  uint numRays;
  uint seed;
  uint jitter;    // 1: one random shift of the edge quantiles a ray (training); 0: none (rendering)
  float padding;  // the uniform share of the sampling mass, spread over the occupied length
  float anneal;   // a in [0, 1]: a candidate's weight w enters as w^a (its share of the length)^(1 - a)
  uint points;    // 1: also each sample's field inputs, its position (box_position.glsl) and direction
PUSH_CONSTANTS_END

#endif

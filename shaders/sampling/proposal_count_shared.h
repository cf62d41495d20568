// The push constants of proposal_count.comp; on the host, vknerf::glsl::ProposalCountPush.
#ifndef VKNERF_SAMPLING_PROPOSAL_COUNT_SHARED_H
#define VKNERF_SAMPLING_PROPOSAL_COUNT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(ProposalCountPush)
  uint numRays;
  uint samplesPerRay;
  uint candidateSpan;  // the most march steps one candidate stands for (>= 1)
PUSH_CONSTANTS_END

#endif

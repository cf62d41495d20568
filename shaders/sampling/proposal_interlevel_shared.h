// The push constants of proposal_interlevel.comp; on the host, vknerf::glsl::InterlevelPush.
#ifndef VKNERF_SAMPLING_PROPOSAL_INTERLEVEL_SHARED_H
#define VKNERF_SAMPLING_PROPOSAL_INTERLEVEL_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(InterlevelPush)
  uint numRays;
  float weight;   // the loss's weight: scales the loss and every gradient
  float epsilon;  // L = sum max(0, w - B)^2 / (w + epsilon)
PUSH_CONSTANTS_END

#endif

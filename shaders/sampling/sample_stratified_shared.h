// The push constants of sample_stratified.comp; on the host, vknerf::glsl::StratifiedPush.
#ifndef VKNERF_SAMPLING_SAMPLE_STRATIFIED_SHARED_H
#define VKNERF_SAMPLING_SAMPLE_STRATIFIED_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(StratifiedPush)
  uint numRays;
  uint samplesPerRay;
  uint seed;
  uint jitter;
PUSH_CONSTANTS_END

#endif

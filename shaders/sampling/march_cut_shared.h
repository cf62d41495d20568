// The push constants of march_cut.comp; on the host, vknerf::glsl::MarchCutPush.
#ifndef VKNERF_SAMPLING_MARCH_CUT_SHARED_H
#define VKNERF_SAMPLING_MARCH_CUT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(MarchCutPush)
  uint numRays;
  uint localSize;
  uint maxGroupsX;
  uint capacity;
  uint rayAlign;
PUSH_CONSTANTS_END

#endif

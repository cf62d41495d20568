// The push constants of march_compact.comp; on the host, vknerf::glsl::MarchCompactPush.
#ifndef VKNERF_SAMPLING_MARCH_COMPACT_SHARED_H
#define VKNERF_SAMPLING_MARCH_COMPACT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(MarchCompactPush)
  uint numRays;
  uint maxSamples;  // slots a ray
PUSH_CONSTANTS_END

#endif

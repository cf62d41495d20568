// The push constants of march_totals.comp; on the host, vknerf::glsl::MarchTotalsPush.
#ifndef VKNERF_SAMPLING_MARCH_TOTALS_SHARED_H
#define VKNERF_SAMPLING_MARCH_TOTALS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(MarchTotalsPush)
  uint numRays;
  uint localSize;
  uint maxGroupsX;
PUSH_CONSTANTS_END

#endif

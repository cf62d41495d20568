// The push constants of occupancy_ema.comp; on the host, vknerf::glsl::OccupancyEmaPush.
#ifndef VKNERF_OCCUPANCY_OCCUPANCY_EMA_SHARED_H
#define VKNERF_OCCUPANCY_OCCUPANCY_EMA_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(OccupancyEmaPush)
  uint numCells;
  float decay;
  float threshold;
  uint capAtMean;
PUSH_CONSTANTS_END

#endif

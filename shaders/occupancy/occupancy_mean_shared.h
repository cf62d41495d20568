// The push constants of occupancy_mean.comp; on the host, vknerf::glsl::OccupancyMeanPush.
#ifndef VKNERF_OCCUPANCY_OCCUPANCY_MEAN_SHARED_H
#define VKNERF_OCCUPANCY_OCCUPANCY_MEAN_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(OccupancyMeanPush)
  uint numCells;
PUSH_CONSTANTS_END

#endif

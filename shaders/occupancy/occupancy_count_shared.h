// The push constants of occupancy_count.comp; on the host, vknerf::glsl::OccupancyCountPush.
#ifndef VKNERF_OCCUPANCY_OCCUPANCY_COUNT_SHARED_H
#define VKNERF_OCCUPANCY_OCCUPANCY_COUNT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(OccupancyCountPush)
  uint numCells;
PUSH_CONSTANTS_END

#endif

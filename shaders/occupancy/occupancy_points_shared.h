// The push constants of occupancy_points.comp; on the host, vknerf::glsl::OccupancyPointsPush.
#ifndef VKNERF_OCCUPANCY_OCCUPANCY_POINTS_SHARED_H
#define VKNERF_OCCUPANCY_OCCUPANCY_POINTS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(OccupancyPointsPush)
  uint resolution;
  uint count;
  uint seed;
  uint randomCells;
  uint cascades;  // cell = cascade * R^3 + local cell; cascade c spans 2^(c - cascades + 1) of the box
PUSH_CONSTANTS_END

#endif

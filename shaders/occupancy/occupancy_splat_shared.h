// The push constants of occupancy_splat.comp; on the host, vknerf::glsl::OccupancySplatPush.
#ifndef VKNERF_OCCUPANCY_OCCUPANCY_SPLAT_SHARED_H
#define VKNERF_OCCUPANCY_OCCUPANCY_SPLAT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(OccupancySplatPush)
  uint count;
  uint stride;     // floats per point in density[] (4 when reading sigma out of a field vec4)
  uint component;  // which of them is the density
PUSH_CONSTANTS_END

#endif

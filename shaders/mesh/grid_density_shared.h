// The push constants of grid_density.comp; on the host, vknerf::glsl::GridDensityPush.
#ifndef VKNERF_MESH_GRID_DENSITY_SHARED_H
#define VKNERF_MESH_GRID_DENSITY_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(GridDensityPush)
  uvec4 n;
  uvec4 blockCount;
  uint first;
  uint count;
PUSH_CONSTANTS_END

#endif

// The push constants of grid_points.comp; on the host, vknerf::glsl::GridPointsPush.
#ifndef VKNERF_MESH_GRID_POINTS_SHARED_H
#define VKNERF_MESH_GRID_POINTS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(GridPointsPush)
  uvec4 n;           // samples per axis (w unused)
  uvec4 blockCount;  // blocks per axis (w unused)
  vec4 origin;
  vec4 spacing;
  vec4 boxMin;
  vec4 boxMax;
  uint first;
  uint count;
PUSH_CONSTANTS_END

#endif

// The push constants of rays.comp; on the host, vknerf::glsl::RaysPush.
#ifndef VKNERF_RAYS_RAYS_SHARED_H
#define VKNERF_RAYS_RAYS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(RaysPush)
  vec4 aabbMin;      // xyz; w = near plane (minimum t)
  vec4 aabbMax;
  uint mode;         // 0: pixels [first, first+count) of camera `camera`; 1: random pixels of random
                     // cameras; 2: random pixels, the rays in runs of one camera each (rays/camera_runs.glsl)
  uint camera;       // mode 0; in modes 1 and 2 the number of cameras
  uint first;        // mode 0: first pixel index; modes 1 and 2: RNG seed
  uint count;        // number of rays
PUSH_CONSTANTS_END

#endif

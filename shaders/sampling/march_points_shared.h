// The push constants of march_points.comp; on the host, vknerf::glsl::MarchPointsPush.
#ifndef VKNERF_SAMPLING_MARCH_POINTS_SHARED_H
#define VKNERF_SAMPLING_MARCH_POINTS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(MarchPointsPush)
  vec4 boxMin;
  vec4 boxMax;
  uint chunkRows;  // rows of each dispatch's chunk
  uint limitBase;  // the chunk's first sample (row_limit.glsl)
  uint midpoints;  // 1: each sample's point is its interval's middle, t + delta / 2; 0: t
PUSH_CONSTANTS_END

#endif

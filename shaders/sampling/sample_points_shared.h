// The push constants of sample_points.comp; on the host, vknerf::glsl::SamplePointsPush.
#ifndef VKNERF_SAMPLING_SAMPLE_POINTS_SHARED_H
#define VKNERF_SAMPLING_SAMPLE_POINTS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(SamplePointsPush)
  vec4 boxMin;
  vec4 boxMax;
  uint count;           // samples in the batch
  uint samplesPerRay;   // N
PUSH_CONSTANTS_END

#endif

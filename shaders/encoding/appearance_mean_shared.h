// The push constants of appearance_mean.comp; on the host, vknerf::glsl::AppearanceMeanPush.
#ifndef VKNERF_ENCODING_APPEARANCE_MEAN_SHARED_H
#define VKNERF_ENCODING_APPEARANCE_MEAN_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(AppearanceMeanPush)
  uint numCameras;
  uint dimsVec4;
PUSH_CONSTANTS_END

#endif

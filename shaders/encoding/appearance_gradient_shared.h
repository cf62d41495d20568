// The push constants of appearance_gradient.comp; on the host,
// vknerf::glsl::AppearanceGradientPush.
#ifndef VKNERF_ENCODING_APPEARANCE_GRADIENT_SHARED_H
#define VKNERF_ENCODING_APPEARANCE_GRADIENT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(AppearanceGradientPush)
  uint numCameras;
  uint maxRays;     // the rays recorded; the device's ray count cuts them further
  uint strideVec4;  // of dL/d(direction input)
  uint offsetVec4;  // the vector's first column / 4
  uint dimsVec4;
PUSH_CONSTANTS_END

#endif

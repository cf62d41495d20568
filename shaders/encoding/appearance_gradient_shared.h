// The push constants of appearance_gradient.comp; on the host,
// vknerf::glsl::AppearanceGradientPush.
#ifndef VKNERF_ENCODING_APPEARANCE_GRADIENT_SHARED_H
#define VKNERF_ENCODING_APPEARANCE_GRADIENT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(AppearanceGradientPush)
  uint numCameras;
  uint maxRays;    // the rays recorded; the device's ray count cuts them further
  uint widthVec4;  // vec4s a row of dL/d(colour pre-activation)
  uint dims;       // floats a vector
PUSH_CONSTANTS_END

#endif

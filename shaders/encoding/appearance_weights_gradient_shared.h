// The push constants of appearance_weights_gradient.comp; on the host,
// vknerf::glsl::AppearanceWeightsGradientPush.
#ifndef VKNERF_ENCODING_APPEARANCE_WEIGHTS_GRADIENT_SHARED_H
#define VKNERF_ENCODING_APPEARANCE_WEIGHTS_GRADIENT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(AppearanceWeightsGradientPush)
  uint numCameras;
  uint dims;       // floats a vector
  uint widthVec4;  // vec4s a row of W_a
PUSH_CONSTANTS_END

#endif

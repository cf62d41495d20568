// The push constants of appearance_bias.comp; on the host, vknerf::glsl::AppearanceBiasPush.
#ifndef VKNERF_ENCODING_APPEARANCE_BIAS_SHARED_H
#define VKNERF_ENCODING_APPEARANCE_BIAS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(AppearanceBiasPush)
  uint count;      // bias rows to write
  uint first;      // the first vector's row in the table
  uint dims;       // floats a vector
  uint widthVec4;  // vec4s a bias row (the colour layer's padded width / 4)
PUSH_CONSTANTS_END

#endif

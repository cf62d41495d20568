// The push constants of random_background.comp; on the host, vknerf::glsl::BackgroundPush.
#ifndef VKNERF_LOSS_RANDOM_BACKGROUND_SHARED_H
#define VKNERF_LOSS_RANDOM_BACKGROUND_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(BackgroundPush)
  vec4 constant;  // rgb, a = 1: the colour in constant mode
  uint random;    // 1: rng01(seed, ray, 100 + channel); 0: the constant
  uint seed;
  uint count;     // rays
PUSH_CONSTANTS_END

#endif

// The push constants of adam.comp; on the host, vknerf::glsl::AdamPush.
#ifndef VKNERF_OPTIM_ADAM_SHARED_H
#define VKNERF_OPTIM_ADAM_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(AdamPush)
  float lr;
  float beta1;
  float beta2;
  float epsilon;
  float correction1;  // 1 / (1 - beta1^t)
  float correction2;  // 1 / (1 - beta2^t)
  uint count;         // parameters
  uint skipZero;      // 1: a parameter whose gradient is exactly 0 keeps p, m and v (sparse rows)
  uint tailIndex;     // index of parameter 4 * (count / 4) in the tail bindings
PUSH_CONSTANTS_END

#endif

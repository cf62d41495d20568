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
  uint skipZeroFrom;  // parameters at and past it whose gradient is exactly 0 keep p, m and v (a multiple of 4)
  uint tailIndex;     // index of parameter 4 * (count / 4) in the tail bindings
  uint body4;         // the vec4s this kernel steps (the rest: adam_sparse.comp)
PUSH_CONSTANTS_END

#endif

// The push constants of adam_sparse.comp; on the host, vknerf::glsl::AdamSparsePush (its first
// six fields are adam.comp's).
#ifndef VKNERF_OPTIM_ADAM_SPARSE_SHARED_H
#define VKNERF_OPTIM_ADAM_SPARSE_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(AdamSparsePush)
  float lr;
  float beta1;
  float beta2;
  float epsilon;
  float correction1;
  float correction2;
  uint count;      // the list's capacity
  uint limitBase;  // row_limit.glsl: the list's length is the device's count
PUSH_CONSTANTS_END

#endif

// The push constants of adam_touched.comp; on the host, vknerf::glsl::AdamTouchedPush.
#ifndef VKNERF_OPTIM_ADAM_TOUCHED_SHARED_H
#define VKNERF_OPTIM_ADAM_TOUCHED_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(AdamTouchedPush)
  uint first4;  // the sparse part: vec4s [first4, first4 + count4)
  uint count4;
PUSH_CONSTANTS_END

#endif

// The push constants of sum_partials.comp; on the host, vknerf::glsl::SumPartialsPush.
#ifndef VKNERF_LOSS_SUM_PARTIALS_SHARED_H
#define VKNERF_LOSS_SUM_PARTIALS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(SumPartialsPush)
  uint count;      // values summed
  uint stride;     // floats from one value to the next
  uint component;  // the value's float within its stride
PUSH_CONSTANTS_END

#endif

// The push constants of kept_rows.comp; on the host, vknerf::glsl::KeptRowsPush.
#ifndef VKNERF_SAMPLING_KEPT_ROWS_SHARED_H
#define VKNERF_SAMPLING_KEPT_ROWS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(KeptRowsPush)
  uint numRays;
PUSH_CONSTANTS_END

#endif

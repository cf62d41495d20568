// The push constants of far_field_directions.comp and far_field_gradient.comp; on the host, vknerf::glsl::FarFieldPush.
#ifndef VKNERF_RENDER_FAR_FIELD_SHARED_H
#define VKNERF_RENDER_FAR_FIELD_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(FarFieldPush)
  uint count;  // rays
PUSH_CONSTANTS_END

#endif

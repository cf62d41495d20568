// The push constants of loss_photometric.comp; on the host, vknerf::glsl::LossPush.
#ifndef VKNERF_LOSS_LOSS_PHOTOMETRIC_SHARED_H
#define VKNERF_LOSS_LOSS_PHOTOMETRIC_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(LossPush)
  uint numRays;
  float gradScale;
  uint firstBinding;  // binding index of pixels0; 0 in the first dispatch, which writes the partials
  uint limitBase;     // row_limit.glsl
PUSH_CONSTANTS_END

#endif

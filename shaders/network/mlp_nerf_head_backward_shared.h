// The specialization and push constants of mlp_nerf_head_backward.comp; on the host,
// vknerf::glsl::MlpHeadBackwardSpec and MlpHeadBackwardPush.
#ifndef VKNERF_NETWORK_MLP_NERF_HEAD_BACKWARD_SHARED_H
#define VKNERF_NETWORK_MLP_NERF_HEAD_BACKWARD_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(MlpHeadBackwardSpec)
  LOCAL_SIZE_X_ID(0)
  SPEC_CONSTANT(1, uint, K4, 64)
  SPEC_CONSTANT(2, uint, WOFF4, 0)
  SPEC_CONSTANT(3, uint, SIGMA_COL, 128)
  SPEC_CONSTANT(4, uint, DENSITY, 0)
  SPEC_CONSTANT(5, uint, COLOUR, 1)  // 0: a density-only forward's backward (the head's comment)
SPEC_CONSTANTS_END

PUSH_CONSTANTS_BEGIN(MlpHeadBackwardPush)
  uint count;
  uint strideDOut4, strideOut4, strideC4, strideF4, strideDF4, strideDC4;
  uint gather;     // row_gather.glsl
  uint limitBase;  // row_limit.glsl: the rows at and past the device limit are left untouched
PUSH_CONSTANTS_END

#endif

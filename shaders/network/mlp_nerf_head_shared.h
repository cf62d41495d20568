// The specialization and push constants of mlp_nerf_head.comp; on the host,
// vknerf::glsl::MlpHeadSpec and MlpHeadPush.
#ifndef VKNERF_NETWORK_MLP_NERF_HEAD_SHARED_H
#define VKNERF_NETWORK_MLP_NERF_HEAD_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(MlpHeadSpec)
  LOCAL_SIZE_X_ID(0)
  SPEC_CONSTANT(1, uint, K4, 64)
  SPEC_CONSTANT(2, uint, WOFF4, 0)
  SPEC_CONSTANT(3, uint, SIGMA_COL, 128)  // multiple of 4
  SPEC_CONSTANT(4, uint, DENSITY, 0)      // MLP_DENSITY_*
  SPEC_CONSTANT(5, uint, COLOUR, 1)       // 0: the density alone, rgb written 0 (C unread)
SPEC_CONSTANTS_END

PUSH_CONSTANTS_BEGIN(MlpHeadPush)
  uint count;
  uint strideC4, strideF4, strideOut4;
  uint limitBase;  // row_limit.glsl
  uint gather;     // row_gather.glsl
PUSH_CONSTANTS_END

#endif

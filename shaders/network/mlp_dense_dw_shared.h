// The specialization and push constants of network/mlp_dense_dw.glsl (mlp_dense_dw*.comp); on the
// host, vknerf::glsl::MlpDenseDwSpec and MlpDenseDwPush.
#ifndef VKNERF_NETWORK_MLP_DENSE_DW_SHARED_H
#define VKNERF_NETWORK_MLP_DENSE_DW_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(MlpDenseDwSpec)
  LOCAL_SIZE_X_ID(0)
  SPEC_CONSTANT(1, uint, K4, 64)
  SPEC_CONSTANT(2, uint, N4, 64)    // row length of the gradient block
  SPEC_CONSTANT(3, uint, N0, 0)     // first column covered by this dispatch
  SPEC_CONSTANT(4, uint, NW, 64)    // columns covered (multiple of NT)
  SPEC_CONSTANT(5, uint, KT, 8)
  SPEC_CONSTANT(6, uint, NT, 8)
  SPEC_CONSTANT(7, uint, U, 8)
  SPEC_CONSTANT(8, uint, GOFF, 0)   // float offset of the block in the gradient buffer
  SPEC_CONSTANT(9, bool, ONES, false)
SPEC_CONSTANTS_END

PUSH_CONSTANTS_BEGIN(MlpDenseDwPush)
  uint count;
  uint strideX4, strideZ4;  // row strides in vec4
  uint iters;
  uint gather;              // row_gather.glsl
  uint limitBase;           // row_limit.glsl
PUSH_CONSTANTS_END

#endif

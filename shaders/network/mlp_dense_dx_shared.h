// The specialization and push constants of mlp_dense_dx.comp; on the host,
// vknerf::glsl::MlpDenseDxSpec and MlpDenseDxPush.
#ifndef VKNERF_NETWORK_MLP_DENSE_DX_SHARED_H
#define VKNERF_NETWORK_MLP_DENSE_DX_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(MlpDenseDxSpec)
  LOCAL_SIZE_X_ID(0)
  SPEC_CONSTANT(1, uint, KA4, 64)
  SPEC_CONSTANT(2, uint, KB4, 0)
  SPEC_CONSTANT(3, uint, N4, 64)
  SPEC_CONSTANT(4, uint, WOFF4, 0)
  SPEC_CONSTANT(5, uint, R, 4)
  SPEC_CONSTANT(6, uint, KBLK, 8)    // divides KA4 (the B part goes 4 at a time)
  SPEC_CONSTANT(7, uint, MODE_A, 2)
  SPEC_CONSTANT(8, uint, MODE_B, 0)
  SPEC_CONSTANT(9, uint, KB_FIRST, 0)  // the B part's first column computed (a multiple of 4): those before are left
  SPEC_CONSTANT(10, uint, N_FIRST, 0)  // dZ's first column read (a multiple of 4): those before are taken as 0
SPEC_CONSTANTS_END

PUSH_CONSTANTS_BEGIN(MlpDenseDxPush)
  uint count;
  uint strideZ4, strideA4, strideDA4, strideDB4;  // row strides in vec4
  uint gather;                                    // row_gather.glsl
  uint limitBase;                                 // row_limit.glsl
PUSH_CONSTANTS_END

#endif

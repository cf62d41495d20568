// The specialization and push constants of mlp_dense.comp; on the host,
// vknerf::glsl::MlpDenseSpec and MlpDensePush.
#ifndef VKNERF_NETWORK_MLP_DENSE_SHARED_H
#define VKNERF_NETWORK_MLP_DENSE_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(MlpDenseSpec)
  LOCAL_SIZE_X_ID(0)
  SPEC_CONSTANT(1, uint, KA4, 64)     // padded width of input A
  SPEC_CONSTANT(2, uint, KB4, 0)      // padded width of input B (0: none)
  SPEC_CONSTANT(3, uint, N4, 64)      // padded output width
  SPEC_CONSTANT(4, uint, NTRUE, 64)   // output columns >= NTRUE are stored as 0
  SPEC_CONSTANT(5, uint, ACT, 1)      // MLP_ACT_*
  SPEC_CONSTANT(6, uint, WOFF4, 0)    // vec4 offset of W in the parameter buffer
  SPEC_CONSTANT(7, uint, R, 4)        // rows per invocation
  SPEC_CONSTANT(8, uint, NB, 8)       // output columns per block (multiple of 4)
  SPEC_CONSTANT(9, uint, ROW_BIAS, 0) // ROW_BIAS_* (network/row_bias_shared.h)
  SPEC_CONSTANT(10, uint, N_FIRST, 0) // output columns before it (a multiple of 4) are neither computed nor stored
SPEC_CONSTANTS_END

PUSH_CONSTANTS_BEGIN(MlpDensePush)
  uint count;
  uint strideA4, strideB4, strideY4;  // row strides in vec4
  uint limitBase;                     // row_limit.glsl
  uint gather;                        // row_gather.glsl
PUSH_CONSTANTS_END

#endif

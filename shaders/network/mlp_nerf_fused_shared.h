// The specialization and push constants of mlp_nerf_fused.comp; on the host,
// vknerf::glsl::MlpFusedSpec and MlpFusedPush.
#ifndef VKNERF_NETWORK_MLP_NERF_FUSED_SHARED_H
#define VKNERF_NETWORK_MLP_NERF_FUSED_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(MlpFusedSpec)
  LOCAL_SIZE_X_ID(0)
  SPEC_CONSTANT(1, uint, R, 4)          // rows per invocation
  SPEC_CONSTANT(2, uint, KP4, 16)       // padded width of the position features
  SPEC_CONSTANT(3, uint, KD4, 16)       // padded width of the direction features
  SPEC_CONSTANT(4, uint, W, 64)         // trunk width (multiple of 8)
  SPEC_CONSTANT(5, uint, DEPTH, 1)      // trunk layers, 1 or 2
  SPEC_CONSTANT(6, uint, V, 16)         // feature width (multiple of 4); sigma is column V
  SPEC_CONSTANT(7, uint, DENSITY, 0)    // MLP_DENSITY_*
  SPEC_CONSTANT(8, uint, KEEP, 0)       // 1: store the activations for backward
  SPEC_CONSTANT(9, uint, NB, 8)         // output columns per block (multiple of 4)
  // vec4 offsets of each layer's weights in the parameter buffer (NerfShape::layers)
  SPEC_CONSTANT(10, uint, T0OFF4, 0)
  SPEC_CONSTANT(11, uint, T1OFF4, 0)
  SPEC_CONSTANT(12, uint, FOFF4, 0)
  SPEC_CONSTANT(13, uint, COFF4, 0)
  SPEC_CONSTANT(14, uint, HOFF4, 0)
  SPEC_CONSTANT(15, uint, UNROLL, 1)     // 1: unroll the output blocks (FUSED_LAYER)
  SPEC_CONSTANT(16, uint, ROW_BIAS, 0)   // the colour layer's bias per row: ROW_BIAS_* (network/row_bias.glsl)
  SPEC_CONSTANT(17, uint, COLOUR, 1)     // 0: the density alone (sigma's column of the feature layer; rgb = 0)
SPEC_CONSTANTS_END

PUSH_CONSTANTS_BEGIN(MlpFusedPush)
  uint count;
  uint strideP4, strideD4, strideOut4;  // row strides in vec4
  uint limitBase;                       // row_limit.glsl
PUSH_CONSTANTS_END

#endif

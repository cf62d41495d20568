// The specialization and push constants of mlp_nerf_density.comp; on the host,
// vknerf::glsl::MlpDensitySpec and MlpDensityPush.
#ifndef VKNERF_NETWORK_MLP_NERF_DENSITY_SHARED_H
#define VKNERF_NETWORK_MLP_NERF_DENSITY_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(MlpDensitySpec)
  LOCAL_SIZE_X_ID(0)
  SPEC_CONSTANT(1, uint, R, 4)        // rows per invocation
  SPEC_CONSTANT(2, uint, K4, 64)      // the trunk's width: the feature layer's input
  SPEC_CONSTANT(3, uint, N4, 68)      // the feature layer's padded width (V + 4)
  SPEC_CONSTANT(4, uint, V, 64)       // sigma's column (a multiple of 4)
  SPEC_CONSTANT(5, uint, WOFF4, 0)    // vec4 offset of the feature layer's weights
  SPEC_CONSTANT(6, uint, DENSITY, 0)  // MLP_DENSITY_*
SPEC_CONSTANTS_END

PUSH_CONSTANTS_BEGIN(MlpDensityPush)
  uint count;
  uint strideH4;   // row stride of H in vec4
  uint limitBase;  // row_limit.glsl
PUSH_CONSTANTS_END

#endif

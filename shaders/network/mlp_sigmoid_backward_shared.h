// The specialization and push constants of mlp_sigmoid_backward.comp; on the host,
// vknerf::glsl::MlpSigmoidBackwardSpec and MlpSigmoidBackwardPush.
#ifndef VKNERF_NETWORK_MLP_SIGMOID_BACKWARD_SHARED_H
#define VKNERF_NETWORK_MLP_SIGMOID_BACKWARD_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(MlpSigmoidBackwardSpec)
  SPEC_CONSTANT(0, uint, N4, 4)
  SPEC_CONSTANT(1, uint, NTRUE, 3)
SPEC_CONSTANTS_END

PUSH_CONSTANTS_BEGIN(MlpSigmoidBackwardPush)
  uint count;  // rows
  uint strideDY4, strideY4, strideDZ4;
PUSH_CONSTANTS_END

#endif

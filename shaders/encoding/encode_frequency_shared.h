// The specialization and push constants of encode_frequency.comp; on the host,
// vknerf::glsl::FrequencySpec and FrequencyPush.
#ifndef VKNERF_ENCODING_ENCODE_FREQUENCY_SHARED_H
#define VKNERF_ENCODING_ENCODE_FREQUENCY_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(FrequencySpec)
  SPEC_CONSTANT(0, uint, DIMS, 3u)           // input components used, 1..4
  SPEC_CONSTANT(1, uint, LEVELS, 10u)        // L
  SPEC_CONSTANT(2, uint, INCLUDE_INPUT, 1u)  // 0 or 1
SPEC_CONSTANTS_END

PUSH_CONSTANTS_BEGIN(FrequencyPush)
  uint count;         // rows
  uint strideVec4;    // row stride in vec4s
  uint offsetVec4;    // first column / 4
PUSH_CONSTANTS_END

#endif

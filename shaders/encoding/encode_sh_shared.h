// The specialization and push constants of encode_sh.comp; on the host,
// vknerf::glsl::ShSpec and ShPush.
#ifndef VKNERF_ENCODING_ENCODE_SH_SHARED_H
#define VKNERF_ENCODING_ENCODE_SH_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(ShSpec)
  SPEC_CONSTANT(0, uint, DEGREE, 4u)  // 1..4
SPEC_CONSTANTS_END

PUSH_CONSTANTS_BEGIN(ShPush)
  uint count;
  uint strideVec4;
  uint offsetVec4;
  uint limitBase;  // row_limit.glsl
  uint gather;     // row_gather.glsl
PUSH_CONSTANTS_END

#endif

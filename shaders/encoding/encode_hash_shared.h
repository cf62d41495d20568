// The push constants of encode_hash.comp and encode_hash_backward.comp; on the host, vknerf::glsl::HashPush.
#ifndef VKNERF_ENCODING_ENCODE_HASH_SHARED_H
#define VKNERF_ENCODING_ENCODE_HASH_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(HashPush)
  uint count;        // rows
  uint strideVec4;   // row stride in vec4s
  uint offsetVec4;   // first column / 4
  uint denseMask;    // bit l: level l is densely indexed
  UVEC4_ARRAY(res, 6);  // resolution of level l at res[l / 4][l % 4] (C++: res[l])
  uint limitBase;    // row_limit.glsl
  uint gather;       // row_gather.glsl (the forward; the backward leaves it 0)
PUSH_CONSTANTS_END
PUSH_CONSTANTS_OFFSET(HashPush, res, 16)

#endif

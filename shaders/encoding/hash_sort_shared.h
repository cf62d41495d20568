// The push constants of encode_hash_backward_count.comp and _scatter.comp (through
// encoding/hash_sort.glsl); on the host, vknerf::glsl::HashSortPush.
#ifndef VKNERF_ENCODING_HASH_SORT_SHARED_H
#define VKNERF_ENCODING_HASH_SORT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(HashSortPush)
  uint count;
  uint strideVec4;
  uint offsetVec4;
  uint denseMask;
  UVEC4_ARRAY(res, 6);  // as encode_hash_shared.h's
  uint rowBase;
  uint levelBegin;
  uint levelEnd;
  uint limitBase;  // row_limit.glsl: the chunk's first row in the limited batch
PUSH_CONSTANTS_END
PUSH_CONSTANTS_OFFSET(HashSortPush, res, 16)

#endif

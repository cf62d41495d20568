// The specialization constants of the hash grid kernels (encode_hash.comp, encode_hash_backward.comp,
// encode_hash_backward_count.comp and _scatter.comp); on the host, vknerf::glsl::HashGridSpec.
#ifndef VKNERF_ENCODING_HASH_GRID_SHARED_H
#define VKNERF_ENCODING_HASH_GRID_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(HashGridSpec)
  SPEC_CONSTANT(0, uint, LEVELS, 16u)
  SPEC_CONSTANT(1, uint, FEATURES, 2u)     // 1, 2, 4 or 8
  SPEC_CONSTANT(2, uint, LOG2_TABLE, 19u)
  SPEC_CONSTANT(3, uint, CONTRACT, 0u)     // 0: the grid spans the box; S: it spans the box contracted
                                           // about its inner cube [-1/S, 1/S]^3 (hashGridContract)
SPEC_CONSTANTS_END

#endif

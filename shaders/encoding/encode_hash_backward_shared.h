// The specialization constant of encode_hash_backward.comp besides hash_grid_shared.h's; on the
// host, vknerf::glsl::HashBackwardSpec.
#ifndef VKNERF_ENCODING_ENCODE_HASH_BACKWARD_SHARED_H
#define VKNERF_ENCODING_ENCODE_HASH_BACKWARD_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(HashBackwardSpec)
  SPEC_CONSTANT(3, uint, MERGE, 0u)  // 1: a subgroup whose lanes all hit one entry adds with one atomic
SPEC_CONSTANTS_END

#endif

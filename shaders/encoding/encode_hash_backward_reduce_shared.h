// The specialization and push constants of encode_hash_backward_reduce.comp; on the host,
// vknerf::glsl::HashReduceSpec and HashReducePush.
#ifndef VKNERF_ENCODING_ENCODE_HASH_BACKWARD_REDUCE_SHARED_H
#define VKNERF_ENCODING_ENCODE_HASH_BACKWARD_REDUCE_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(HashReduceSpec)
  SPEC_CONSTANT(0, uint, FEATURES, 2u)
  SPEC_CONSTANT(1, uint, CHUNK, 256u)  // slots per invocation
  SPEC_CONSTANT(2, uint, STAGE, 0u)
SPEC_CONSTANTS_END

PUSH_CONSTANTS_BEGIN(HashReducePush)
  uint slots;      // slots of this pass
  uint entryBase;  // table entry of the pass's entry 0
  uint entries;    // entries of this pass: cursor's length (its binding may be longer)
PUSH_CONSTANTS_END

#endif

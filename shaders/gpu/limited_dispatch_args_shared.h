// The push constants of limited_dispatch_args.comp; on the host, vknerf::glsl::LimitedDispatchArgsPush.
#ifndef VKNERF_GPU_LIMITED_DISPATCH_ARGS_SHARED_H
#define VKNERF_GPU_LIMITED_DISPATCH_ARGS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(LimitedDispatchArgsPush)
  uint count;      // rows of the batch as recorded
  uint chunkRows;
  uint chunks;
  uint kinds;      // entries per chunk (1..4)
  uvec4 rowsPerGroup;
PUSH_CONSTANTS_END
PUSH_CONSTANTS_OFFSET(LimitedDispatchArgsPush, rowsPerGroup, 16)

#endif

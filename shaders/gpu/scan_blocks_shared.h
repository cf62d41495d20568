// The push constants of scan_blocks.comp; on the host, vknerf::glsl::ScanBlocksPush.
#ifndef VKNERF_GPU_SCAN_BLOCKS_SHARED_H
#define VKNERF_GPU_SCAN_BLOCKS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(ScanBlocksPush)
  uint inputCount;
  uint outputCount;
  uint clampTo;
  uint writeBlockSums;
PUSH_CONSTANTS_END

#endif

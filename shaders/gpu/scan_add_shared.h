// The push constants of scan_add.comp; on the host, vknerf::glsl::ScanAddPush.
#ifndef VKNERF_GPU_SCAN_ADD_SHARED_H
#define VKNERF_GPU_SCAN_ADD_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(ScanAddPush)
  uint outputCount;
  uint clampTo;
PUSH_CONSTANTS_END

#endif

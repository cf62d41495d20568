// The push constants of camera_correct.comp; on the host, vknerf::glsl::CameraCorrectPush.
#ifndef VKNERF_RAYS_CAMERA_CORRECT_SHARED_H
#define VKNERF_RAYS_CAMERA_CORRECT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(CameraCorrectPush)
  uint count;  // cameras
PUSH_CONSTANTS_END

#endif

// The push constants of camera_gradient.comp; on the host,
// vknerf::glsl::CameraGradientPush.
#ifndef VKNERF_RAYS_CAMERA_GRADIENT_SHARED_H
#define VKNERF_RAYS_CAMERA_GRADIENT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(CameraGradientPush)
  vec4 positionScale;  // xyz: d p / d x of the world-to-[-1, 1]^3 map the samples' positions went through
  uint numCameras;
  uint maxRays;        // the rays recorded; the device's ray count cuts them further
  float penalty;       // L2 weight: the gradient gains penalty * correction
  uint writePenaltyValues;  // write each camera's penalty, penalty / 2 |correction|^2 (binding 9)
PUSH_CONSTANTS_END

#endif

// The push constants of write_render_target.comp; on the host, vknerf::glsl::RenderTargetPush.
#ifndef VKNERF_RENDER_WRITE_RENDER_TARGET_SHARED_H
#define VKNERF_RENDER_WRITE_RENDER_TARGET_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(RenderTargetPush)
  uint first;        // pixel index of ray 0 of the block
  uint count;        // rays in the block
  uint width;        // of the view, pixels
  uint channel;      // 0: colour, 1: depth (vknerf::RenderChannel)
  float depthScale;  // depth channel: written grey = depth * depthScale
PUSH_CONSTANTS_END

#endif

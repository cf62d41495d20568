#version 450
#extension GL_GOOGLE_include_directive : require
// Appearance embedding, backward: the gradient of the loss with respect to each photo's vector,
// the sum of dL/d(appearance columns) over the rows of the photo's rays in the batch (ray r's rows
// [rowOffsets[r], rowOffsets[r + 1]) of dDir: every marched sample, or those kept before early
// termination). One workgroup per photo (gpu/per_camera_sum.glsl: the same sum at every run, no float
// atomics). Writes (does not add to) the gradient. ref: src/reference/encoding/appearance.h.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer PixelIds { uvec2 pixelIds[]; };    // (camera, pixel) per ray
layout(std430, binding = 1) readonly buffer RowOffsets { uint rowOffsets[]; };  // ray -> its rows of dDir
layout(std430, binding = 2) readonly buffer DirGradient { vec4 dDir[]; };
layout(std430, binding = 3) writeonly buffer Grads { vec4 grads[]; };
layout(std430, binding = 4) readonly buffer RayCount { uint rayCount; };

#include "encoding/appearance_gradient_shared.h"
#define PER_CAMERA_VEC4 16u  // AppearanceEmbedding::kMaxDims / 4
#include "gpu/per_camera_sum.glsl"

void main() {
  uint c = gl_WorkGroupID.x, lane = gl_LocalInvocationID.x;
  uint n = min(pc.maxRays, rayCount);
  perCameraClear();
  FOR_EACH_CAMERA_RAY(r, n) {
    for (uint q = rowOffsets[r], end = rowOffsets[r + 1u]; q < end; ++q)
      for (uint k = 0u; k < pc.dimsVec4; ++k)
        perCameraScratch[lane * PER_CAMERA_VEC4 + k] += dDir[q * pc.strideVec4 + pc.offsetVec4 + k];
  }
  perCameraReduce(pc.dimsVec4);
  if (lane == 0u)
    for (uint k = 0u; k < pc.dimsVec4; ++k) grads[c * pc.dimsVec4 + k] = perCameraScratch[k];
}

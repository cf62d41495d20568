#version 450
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
// Appearance embedding, backward: the gradient of the loss with respect to each photo's vector,
// the sum of dL/d(appearance columns) over the rows of the photo's rays in the batch (ray r's rows
// [rowOffsets[r], rowOffsets[r + 1]) of dDir: every marched sample, or those kept before early
// termination). One workgroup per photo (gpu/per_camera_sum.glsl: the same sum at every run, no
// float atomics). Writes (does not add to) the gradient. ref: src/reference/encoding/appearance.h.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer PixelIds { uvec2 pixelIds[]; };    // (camera, pixel) per ray
layout(std430, binding = 1) readonly buffer RowOffsets { uint rowOffsets[]; };  // ray -> its rows of dDir
layout(std430, binding = 2) readonly buffer DirGradient { vec4 dDir[]; };
layout(std430, binding = 3) writeonly buffer Grads { vec4 grads[]; };
layout(std430, binding = 4) readonly buffer RayCount { uint rayCount; };

#include "encoding/appearance_gradient_shared.h"
#include "gpu/per_camera_sum.glsl"

// The vector's vec4s a lane keeps in registers (constant indices once unrolled).
const uint MAX_VEC4 = 16u;

void main() {
  uint c = gl_WorkGroupID.x;
  uint n = min(pc.maxRays, rayCount);
  vec4 acc[MAX_VEC4];
  [[unroll]] for (uint k = 0u; k < MAX_VEC4; ++k) acc[k] = vec4(0.0);
  FOR_EACH_CAMERA_RAY(r, n) {
    for (uint q = rowOffsets[r], end = rowOffsets[r + 1u]; q < end; ++q) {
      uint base = q * pc.strideVec4 + pc.offsetVec4;
      [[unroll]] for (uint k = 0u; k < MAX_VEC4; ++k)
        if (k < pc.dimsVec4) acc[k] += dDir[base + k];
    }
  }
  [[unroll]] for (uint k = 0u; k < MAX_VEC4; ++k) {
    if (k >= pc.dimsVec4) break;  // uniform: every lane leaves together
    vec4 total = perCameraSum(acc[k]);
    if (gl_LocalInvocationID.x == 0u) grads[c * pc.dimsVec4 + k] = total;
  }
}

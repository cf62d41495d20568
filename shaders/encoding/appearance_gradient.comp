#version 450
#extension GL_GOOGLE_include_directive : require
// Appearance embedding, backward: the gradient of the loss with respect to each photo's vector,
// the sum of dL/d(appearance columns) over the rows of the photo's rays in the batch. The batch
// comes in runs of one photo each, and a ray's rows follow its own (rowOffsets), so a photo's rows
// are consecutive: a workgroup sums a photo's rows, every lane busy (gpu/per_camera_sum.glsl: the
// same sum at every run, no float atomics). Writes (does not add to) the gradient.
// ref: src/reference/encoding/appearance.h.
#include "gpu/per_camera_sum_shared.h"

layout(local_size_x = PER_CAMERA_LANES) in;

layout(std430, binding = 0) readonly buffer PixelIds { uvec2 pixelIds[]; };     // (camera, pixel) per ray
layout(std430, binding = 1) readonly buffer RowOffsets { uint rowOffsets[]; };  // ray -> its rows of dDir
layout(std430, binding = 2) readonly buffer DirGradient { vec4 dDir[]; };
layout(std430, binding = 3) writeonly buffer Grads { vec4 grads[]; };
layout(std430, binding = 4) readonly buffer RayCount { uint rayCount; };

#include "encoding/appearance_gradient_shared.h"
#include "gpu/per_camera_sum.glsl"

void main() {
  uint lane = gl_LocalInvocationID.x, width = pc.dimsVec4, n = min(pc.maxRays, rayCount);
  for (uint c = gl_WorkGroupID.x; c < pc.numCameras; c += gl_NumWorkGroups.x) {
    uvec2 run = perCameraRays(c, pc.maxRays, n, pc.numCameras);
    uint begin = rowOffsets[run.x], end = rowOffsets[run.y];
    for (uint k = 0u; k < width; ++k) {
      vec4 s = vec4(0.0);
      for (uint q = begin + lane; q < end; q += PER_CAMERA_LANES) s += dDir[q * pc.strideVec4 + pc.offsetVec4 + k];
      perCameraStore(k, s);
    }
    perCameraReduce(width);
    if (lane == 0u)
      for (uint k = 0u; k < width; ++k) grads[c * width + k] = perCameraScratch[k];
    perCameraDone();
  }
}

#version 450
#extension GL_GOOGLE_include_directive : require
// Appearance embedding, backward: the gradient of the loss with respect to each photo's vector,
// the sum over the photo's rays in the batch of their sums of dL/d(appearance columns)
// (appearance_ray_sums.comp). A workgroup sums a run of photos (gpu/per_camera_sum.glsl: the same
// sum at every run, no float atomics). Writes (does not add to) the gradient.
// ref: src/reference/encoding/appearance.h.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer PixelIds { uvec2 pixelIds[]; };  // (camera, pixel) per ray
layout(std430, binding = 1) readonly buffer RaySums { vec4 raySums[]; };     // dimsVec4 per ray
layout(std430, binding = 2) writeonly buffer Grads { vec4 grads[]; };
layout(std430, binding = 3) readonly buffer RayCount { uint rayCount; };

#include "encoding/appearance_gradient_shared.h"
#include "gpu/per_camera_sum.glsl"

void main() {
  uint lane = gl_LocalInvocationID.x, width = pc.dimsVec4;
  uint n = min(pc.maxRays, rayCount), group = perCameraGroup(width);
  perCameraClear();
  for (uint r = lane; r < n; r += 64u) {
    uint slot = perCameraSlot(r, width);
    if (slot < group)
      for (uint k = 0u; k < width; ++k) perCameraScratch[perCameraIndex(lane, slot, width, k)] += raySums[r * width + k];
  }
  perCameraReduce(width);
  if (lane != 0u) return;
  for (uint slot = 0u, c = perCameraFirst(width); slot < group && c < pc.numCameras; ++slot, ++c)
    for (uint k = 0u; k < width; ++k) grads[c * width + k] = perCameraScratch[slot * width + k];
}

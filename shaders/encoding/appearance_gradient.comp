#version 450
#extension GL_GOOGLE_include_directive : require
// Appearance embedding, backward, per photo: g, the sum of dL/d(colour pre-activation) over the rows
// of the photo's rays (the gradient of its bias row), kept for the weights' gradient
// (appearance_weights_gradient.comp), and the gradient of its vector, W_a g. The batch comes in runs
// of one photo each, and a ray's rows follow its own (rowOffsets), so a photo's rows are consecutive:
// a workgroup sums a photo's rows, every lane busy (gpu/per_camera_sum.glsl: the same sum at every
// run, no float atomics). Writes (does not add to) both. ref: tests/reference/encoding/appearance.h.
#include "gpu/per_camera_sum_shared.h"

layout(local_size_x = PER_CAMERA_LANES) in;

layout(std430, binding = 0) readonly buffer PixelIds { uvec2 pixelIds[]; };     // (camera, pixel) per ray
layout(std430, binding = 1) readonly buffer RowOffsets { uint rowOffsets[]; };  // ray -> its rows of dColour
// A texel buffer: imageLoad is vectorised on lavapipe, a per-lane SSBO load a loop over the lanes.
layout(binding = 2, rgba32f) uniform readonly imageBuffer ColourGradient;
layout(std430, binding = 3) readonly buffer Weights { vec4 weights[]; };        // W_a: dims rows of widthVec4
layout(std430, binding = 4) writeonly buffer PhotoSums { vec4 photoSums[]; };   // g: widthVec4 a photo
layout(std430, binding = 5) writeonly buffer Grads { float grads[]; };          // dims a photo
layout(std430, binding = 6) readonly buffer RayCount { uint rayCount; };

#include "encoding/appearance_gradient_shared.h"
#include "gpu/per_camera_sum.glsl"

void main() {
  uint lane = gl_LocalInvocationID.x, width = pc.widthVec4, n = min(pc.maxRays, rayCount);
  for (uint c = gl_WorkGroupID.x; c < pc.numCameras; c += gl_NumWorkGroups.x) {
    uvec2 run = perCameraRays(c, pc.maxRays, n, pc.numCameras);
    uint begin = rowOffsets[run.x], end = rowOffsets[run.y];
    for (uint k = 0u; k < width; ++k) {
      vec4 s = vec4(0.0);
      for (uint q = begin + lane; q < end; q += PER_CAMERA_LANES) s += imageLoad(ColourGradient, int(q * width + k));
      perCameraStore(k, s);
    }
    perCameraReduce(width);
    if (lane == 0u)
      for (uint k = 0u; k < width; ++k) photoSums[c * width + k] = perCameraScratch[k];
    for (uint k = lane; k < pc.dims; k += PER_CAMERA_LANES) {
      float g = 0.0;
      for (uint q = 0u; q < width; ++q) g += dot(weights[k * width + q], perCameraScratch[q]);
      grads[c * pc.dims + k] = g;
    }
    perCameraDone();
  }
}

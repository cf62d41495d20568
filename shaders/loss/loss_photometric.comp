#version 450
// Photometric MSE loss per ray: the target is the training pixel (RGBA8) alpha-blended over that
// ray's background; L = sum over rays and rgb of (pred - target)^2 / (3 R). Writes
// gradScale * dL/dpred (opacity component 0) and one partial sum of squared errors per workgroup,
// reduced in shared memory so no float atomics are needed.
#extension GL_GOOGLE_include_directive : require
#include "rays/camera.glsl"

layout(local_size_x = 128) in;

layout(std430, binding = 0) readonly buffer Pred { vec4 pred[]; };            // (r, g, b, opacity)
layout(std430, binding = 1) readonly buffer PixelIds { uvec2 pixelIds[]; };   // (camera, pixel)
layout(std430, binding = 2) readonly buffer Images { uint pixels[]; };        // RGBA8, R low byte
layout(std430, binding = 3) readonly buffer Cameras { Camera cameras[]; };
layout(std430, binding = 4) readonly buffer Background { vec4 background[]; };
layout(std430, binding = 5) writeonly buffer DPred { vec4 dPred[]; };
layout(std430, binding = 6) writeonly buffer Partials { float partials[]; };  // one per workgroup

layout(push_constant) uniform Push {
  uint numRays;
  float gradScale;
} pc;

shared float sums[128];

void main() {
  uint i = gl_GlobalInvocationID.x;
  uint l = gl_LocalInvocationID.x;
  float sq = 0.0;
  if (i < pc.numRays) {
    uvec2 id = pixelIds[i];
    vec4 px = unpackUnorm4x8(pixels[cameras[id.x].size.z + id.y]);
    vec3 target = px.rgb * px.a + background[i].rgb * (1.0 - px.a);
    vec3 e = pred[i].rgb - target;
    sq = dot(e, e);
    dPred[i] = vec4(e * (pc.gradScale * 2.0 / (3.0 * float(pc.numRays))), 0.0);
  }
  sums[l] = sq;
  barrier();
  for (uint s = gl_WorkGroupSize.x / 2u; s > 0u; s >>= 1u) {
    if (l < s) sums[l] += sums[l + s];
    barrier();
  }
  if (l == 0u) partials[gl_WorkGroupID.x] = sums[0];
}

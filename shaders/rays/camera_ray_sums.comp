#version 450
#extension GL_GOOGLE_include_directive : require
// Camera refinement, backward, first pass: one invocation per ray sums, over the ray's samples
// that trained, the two terms camera_gradient.comp needs of it: t (d x dL/dx) and dL/dx, into
// raySums[2r] and raySums[2r + 1]. camera_gradient.comp then sums these per camera. Summing a
// ray's samples here, with every lane busy, leaves the per-camera pass (whose lanes each meet only
// their own camera's rays) one read per ray.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };                // (o, t_near), (d, t_far)
layout(std430, binding = 1) readonly buffer MarchedOffsets { uint marched[]; };  // ray -> its samples (t)
layout(std430, binding = 2) readonly buffer RowOffsets { uint rowOffsets[]; };   // ray -> its rows of dP
layout(std430, binding = 3) readonly buffer Samples { vec2 samples[]; };         // (t, delta)
layout(std430, binding = 4) readonly buffer PositionGradient { vec4 dP[]; };     // dL/dp per row
layout(std430, binding = 5) writeonly buffer RaySums { vec4 raySums[]; };        // 2 per ray
layout(std430, binding = 6) readonly buffer RayCount { uint rayCount; };

#include "rays/camera_gradient_shared.h"

void main() {
  uint r = gl_GlobalInvocationID.x;
  if (r >= min(pc.maxRays, rayCount)) return;
  vec3 d = rays[2u * r + 1u].xyz;
  vec3 a = vec3(0.0), b = vec3(0.0);
  uint m = marched[r];
  for (uint q = rowOffsets[r], end = rowOffsets[r + 1u]; q < end; ++q, ++m) {
    vec3 gx = dP[q].xyz * pc.positionScale.xyz;
    b += gx;
    a += samples[m].x * cross(d, gx);
  }
  raySums[2u * r] = vec4(a, 0.0);
  raySums[2u * r + 1u] = vec4(b, 0.0);
}

#version 450
#extension GL_GOOGLE_include_directive : require
// Camera refinement, backward: the gradient of the loss with respect to each camera's correction
// (w, tau) (camera_correct.comp), from dL/dp at every sample the batch trained on. A sample lies at
// x = o + t d with o the camera's corrected centre and d = exp(w) d0 its ray's corrected direction
// (t fixed: the march's choice of samples is not differentiated), so
//   dL/dtau = sum dL/dx,   dL/dw = J_l(w)^T sum t (d x dL/dx)
// over the camera's rays and their samples, plus penalty * (w, tau) from the L2 term that keeps
// each pose near the one it was given. One workgroup per camera (gpu/per_camera_sum.glsl: the same
// sum at every run, no float atomics). Writes (does not add to) the gradient. ref: tests/unit/rays.
#include "rays/so3.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };                 // (o, t_near), (d, t_far)
layout(std430, binding = 1) readonly buffer PixelIds { uvec2 pixelIds[]; };        // (camera, pixel)
layout(std430, binding = 2) readonly buffer MarchedOffsets { uint marched[]; };   // ray -> its samples (t)
layout(std430, binding = 3) readonly buffer RowOffsets { uint rowOffsets[]; };    // ray -> its rows of dP
layout(std430, binding = 4) readonly buffer Samples { vec2 samples[]; };          // (t, delta)
layout(std430, binding = 5) readonly buffer PositionGradient { vec4 dP[]; };      // dL/dp per row
layout(std430, binding = 6) readonly buffer Corrections { float corrections[]; };  // 6 per camera
layout(std430, binding = 7) writeonly buffer Grads { float grads[]; };
layout(std430, binding = 8) readonly buffer RayCount { uint rayCount; };

#include "rays/camera_gradient_shared.h"
#define PER_CAMERA_VEC4 2u  // sum t (d x dL/dx), sum dL/dx
#include "gpu/per_camera_sum.glsl"

void main() {
  uint c = gl_WorkGroupID.x;
  uint n = min(pc.maxRays, rayCount);
  vec3 a = vec3(0.0), b = vec3(0.0);
  FOR_EACH_CAMERA_RAY(r, n) {
    vec3 d = rays[2u * r + 1u].xyz;
    uint m = marched[r];
    for (uint q = rowOffsets[r], end = rowOffsets[r + 1u]; q < end; ++q, ++m) {
      vec3 gx = dP[q].xyz * pc.positionScale.xyz;
      b += gx;
      a += samples[m].x * cross(d, gx);
    }
  }
  perCameraScratch[2u * gl_LocalInvocationID.x] = vec4(a, 0.0);
  perCameraScratch[2u * gl_LocalInvocationID.x + 1u] = vec4(b, 0.0);
  perCameraReduce(2u);
  if (gl_LocalInvocationID.x != 0u) return;
  vec3 sumW = perCameraScratch[0].xyz, sumTau = perCameraScratch[1].xyz;
  vec3 w = vec3(corrections[6u * c], corrections[6u * c + 1u], corrections[6u * c + 2u]);
  vec3 tau = vec3(corrections[6u * c + 3u], corrections[6u * c + 4u], corrections[6u * c + 5u]);
  vec3 gw = transpose(so3LeftJacobian(w)) * sumW + pc.penalty * w;
  vec3 gt = sumTau + pc.penalty * tau;
  for (int k = 0; k < 3; ++k) {
    grads[6u * c + uint(k)] = gw[k];
    grads[6u * c + 3u + uint(k)] = gt[k];
  }
}

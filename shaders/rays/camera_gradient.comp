#version 450
#extension GL_GOOGLE_include_directive : require
// Camera refinement, backward: the gradient of the loss with respect to each camera's correction
// (w, tau) (camera_correct.comp), from dL/dp at every sample the batch trained on. A sample lies at
// x = o + t d with o the camera's corrected centre and d = exp(w) d0 its ray's corrected direction
// (t fixed: the march's choice of samples is not differentiated), so
//   dL/dtau = sum dL/dx,   dL/dw = J_l(w)^T sum t (d x dL/dx)
// over the camera's rays and their samples, plus penalty * (w, tau) from the L2 term that keeps
// each pose near the one it was given. A workgroup sums a camera's run of rays (the batch comes in
// runs of one camera each; gpu/per_camera_sum.glsl: the same sum at every run, no float atomics),
// a lane a ray's samples at a time. Writes (does not add to) the gradient, and with
// pc.writePenaltyValues each camera's penalty, penalty / 2 |(w, tau)|^2 (the loss's report).
// ref: tests/unit/rays.
#include "rays/so3.glsl"

#include "gpu/per_camera_sum_shared.h"

layout(local_size_x = PER_CAMERA_LANES) in;

layout(std430, binding = 0) readonly buffer PixelIds { uvec2 pixelIds[]; };        // (camera, pixel)
layout(std430, binding = 1) readonly buffer Rays { vec4 rays[]; };                 // (o, t_near), (d, t_far)
layout(std430, binding = 2) readonly buffer MarchedOffsets { uint marched[]; };    // ray -> its samples (t)
layout(std430, binding = 3) readonly buffer RowOffsets { uint rowOffsets[]; };     // ray -> its rows of dP
layout(std430, binding = 4) readonly buffer Samples { vec2 samples[]; };           // (t, delta)
layout(std430, binding = 5) readonly buffer PositionGradient { vec4 dP[]; };       // dL/dp per row
layout(std430, binding = 6) readonly buffer Corrections { float corrections[]; };  // 6 per camera
layout(std430, binding = 7) writeonly buffer Grads { float grads[]; };
layout(std430, binding = 8) readonly buffer RayCount { uint rayCount; };
layout(std430, binding = 9) writeonly buffer PenaltyValues { float penaltyValues[]; };  // per camera

#include "rays/camera_gradient_shared.h"
#include "gpu/per_camera_sum.glsl"

void main() {
  uint lane = gl_LocalInvocationID.x, n = min(pc.maxRays, rayCount);
  for (uint c = gl_WorkGroupID.x; c < pc.numCameras; c += gl_NumWorkGroups.x) {
    uvec2 run = perCameraRays(c, pc.maxRays, n, pc.numCameras);
    vec3 sumW = vec3(0.0), sumTau = vec3(0.0);  // sum t (d x dL/dx), sum dL/dx
    for (uint r = run.x + lane; r < run.y; r += PER_CAMERA_LANES) {
      vec3 d = rays[2u * r + 1u].xyz;
      uint m = marched[r];
      for (uint q = rowOffsets[r], end = rowOffsets[r + 1u]; q < end; ++q, ++m) {
        vec3 gx = dP[q].xyz * pc.positionScale.xyz;
        sumTau += gx;
        sumW += samples[m].x * cross(d, gx);
      }
    }
    perCameraStore(0u, vec4(sumW, 0.0));
    perCameraStore(1u, vec4(sumTau, 0.0));
    perCameraReduce(2u);
    if (lane == 0u) {
      vec3 w = vec3(corrections[6u * c], corrections[6u * c + 1u], corrections[6u * c + 2u]);
      vec3 tau = vec3(corrections[6u * c + 3u], corrections[6u * c + 4u], corrections[6u * c + 5u]);
      vec3 gw = transpose(so3LeftJacobian(w)) * perCameraScratch[0].xyz + pc.penalty * w;
      vec3 gt = perCameraScratch[1].xyz + pc.penalty * tau;
      if (pc.writePenaltyValues != 0u) penaltyValues[c] = 0.5 * pc.penalty * (dot(w, w) + dot(tau, tau));
      for (int k = 0; k < 3; ++k) {
        grads[6u * c + uint(k)] = gw[k];
        grads[6u * c + 3u + uint(k)] = gt[k];
      }
    }
    perCameraDone();
  }
}

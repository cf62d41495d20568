#version 450
#extension GL_GOOGLE_include_directive : require
// Camera refinement, backward: the gradient of the loss with respect to each camera's correction
// (w, tau) (camera_correct.comp), from dL/dp at every sample the batch trained on. A sample lies at
// x = o + t d with o the camera's corrected centre and d = exp(w) d0 its ray's corrected direction
// (t fixed: the march's choice of samples is not differentiated), so
//   dL/dtau = sum dL/dx,   dL/dw = J_l(w)^T sum t (d x dL/dx)
// over the camera's rays and their samples, plus penalty * (w, tau) from the L2 term that keeps
// each pose near the one it was given. camera_ray_sums.comp sums each ray's samples; here a
// workgroup sums the rays of a run of cameras (gpu/per_camera_sum.glsl: the same sum at every run,
// no float atomics). Writes (does not add to) the gradient. ref: tests/unit/rays.
#include "rays/so3.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer PixelIds { uvec2 pixelIds[]; };        // (camera, pixel)
layout(std430, binding = 1) readonly buffer RaySums { vec4 raySums[]; };           // 2 per ray
layout(std430, binding = 2) readonly buffer Corrections { float corrections[]; };  // 6 per camera
layout(std430, binding = 3) writeonly buffer Grads { float grads[]; };
layout(std430, binding = 4) readonly buffer RayCount { uint rayCount; };

#include "rays/camera_gradient_shared.h"
#include "gpu/per_camera_sum.glsl"

const uint WIDTH = 2u;  // sum t (d x dL/dx), sum dL/dx

void main() {
  uint lane = gl_LocalInvocationID.x;
  uint n = min(pc.maxRays, rayCount), group = perCameraGroup(WIDTH);
  perCameraClear();
  for (uint r = lane; r < n; r += 64u) {
    uint slot = perCameraSlot(r, WIDTH);
    if (slot < group) {
      perCameraScratch[perCameraIndex(lane, slot, WIDTH, 0u)] += raySums[2u * r];
      perCameraScratch[perCameraIndex(lane, slot, WIDTH, 1u)] += raySums[2u * r + 1u];
    }
  }
  perCameraReduce(WIDTH);
  if (lane != 0u) return;
  for (uint slot = 0u, c = perCameraFirst(WIDTH); slot < group && c < pc.numCameras; ++slot, ++c) {
    vec3 sumW = perCameraScratch[slot * WIDTH].xyz, sumTau = perCameraScratch[slot * WIDTH + 1u].xyz;
    vec3 w = vec3(corrections[6u * c], corrections[6u * c + 1u], corrections[6u * c + 2u]);
    vec3 tau = vec3(corrections[6u * c + 3u], corrections[6u * c + 4u], corrections[6u * c + 5u]);
    vec3 gw = transpose(so3LeftJacobian(w)) * sumW + pc.penalty * w;
    vec3 gt = sumTau + pc.penalty * tau;
    for (int k = 0; k < 3; ++k) {
      grads[6u * c + uint(k)] = gw[k];
      grads[6u * c + 3u + uint(k)] = gt[k];
    }
  }
}

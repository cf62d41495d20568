#version 450
#extension GL_GOOGLE_include_directive : require
// Camera refinement, forward: each camera's pose with its learned correction (w, tau), 6 floats,
// applied (nerfstudio's SO3xR3, in the world frame): the rotation becomes exp(w) R, the centre
// c + tau. Every other field (intrinsics, image placement, lens) is copied. One invocation per camera.
// ref::correctedPose.
#include "rays/camera.glsl"
#include "rays/so3.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Cameras { Camera cameras[]; };
layout(std430, binding = 1) readonly buffer Corrections { float corrections[]; };  // 6 per camera
layout(std430, binding = 2) writeonly buffer Corrected { Camera corrected[]; };

#include "rays/camera_correct_shared.h"

void main() {
  uint c = gl_GlobalInvocationID.x;
  if (c >= pc.count) return;
  Camera cam = cameras[c];
  vec3 w = vec3(corrections[6u * c], corrections[6u * c + 1u], corrections[6u * c + 2u]);
  vec3 tau = vec3(corrections[6u * c + 3u], corrections[6u * c + 4u], corrections[6u * c + 5u]);
  mat3 E = so3Exp(w);
  // Rows of R' = E R: row i is sum_k E[i][k] R[k] (GLSL indexes E[column][row]).
  vec4 rows[3];
  for (int i = 0; i < 3; ++i) {
    vec3 r = E[0][i] * cam.c2w[0].xyz + E[1][i] * cam.c2w[1].xyz + E[2][i] * cam.c2w[2].xyz;
    rows[i] = vec4(r, cam.c2w[i].w + tau[i]);
  }
  cam.c2w[0] = rows[0];
  cam.c2w[1] = rows[1];
  cam.c2w[2] = rows[2];
  corrected[c] = cam;
}

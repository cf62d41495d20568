#version 450
// Ray generation: one ray per invocation, for a whole image (render) or for random pixels drawn
// across all training images (training: each ray's camera at random, or the batch in runs of one
// camera each, rays/camera_runs.glsl). Writes (o, t_near), (d, t_far) and the (camera, pixel) id.
#extension GL_GOOGLE_include_directive : require
#include "rays/camera.glsl"
#include "common/rng.glsl"
#include "rays/camera_runs.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Cameras { Camera cameras[]; };
layout(std430, binding = 1) writeonly buffer Rays { vec4 rays[]; };       // 2 per ray
layout(std430, binding = 2) writeonly buffer PixelIds { uvec2 pixelIds[]; };  // (camera, pixel)

#include "rays/rays_shared.h"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  uint cam, pixel;
  if (pc.mode == 0u) {
    cam = pc.camera;
    pixel = pc.first + i;
  } else {
    cam = pc.mode == 1u ? rngUint(pc.first, i, 0u) % pc.camera
                        : (cameraRunOfRay(i, pc.count, pc.camera) + rngUint(pc.first, 0u, 2u) % pc.camera) % pc.camera;
    uvec4 s = cameras[cam].size;
    pixel = rngUint(pc.first, i, 1u) % (s.x * s.y);
  }
  Camera c = cameras[cam];
  vec3 o, d;
  cameraRay(c, pixel % c.size.x, pixel / c.size.x, o, d);
  vec2 t = intersectAabb(o, d, pc.aabbMin.xyz, pc.aabbMax.xyz, pc.aabbMin.w);
  rays[2 * i] = vec4(o, t.x);
  rays[2 * i + 1] = vec4(d, t.y);
  pixelIds[i] = uvec2(cam, pixel);
}

// Pinhole camera in the nerf_synthetic / OpenGL convention: the camera looks down -Z, +Y is up,
// +X right; image rows grow downwards. Layout mirrors vknerf::CameraGpu (src/nerf/camera_gpu.h).
#ifndef VKNERF_CAMERA_GLSL
#define VKNERF_CAMERA_GLSL

struct Camera {
  vec4 intrinsics;  // fx, fy, cx, cy (pixels)
  vec4 c2w[3];      // rows of the 3x4 camera-to-world matrix
  uvec4 size;       // width, height, first pixel of this image in its pixel binding, that binding's index
};

// Ray through the centre of pixel (x, y): origin and unit direction in world space.
void cameraRay(Camera cam, uint x, uint y, out vec3 origin, out vec3 dir) {
  vec3 dc = vec3((float(x) + 0.5 - cam.intrinsics.z) / cam.intrinsics.x,
                 -(float(y) + 0.5 - cam.intrinsics.w) / cam.intrinsics.y, -1.0);
  dir = normalize(vec3(dot(cam.c2w[0].xyz, dc), dot(cam.c2w[1].xyz, dc), dot(cam.c2w[2].xyz, dc)));
  origin = vec3(cam.c2w[0].w, cam.c2w[1].w, cam.c2w[2].w);
}

// Slab test against an axis-aligned box. Returns (t_near, t_far) clipped to t >= tMin; a miss
// returns (-1, -1). A zero direction component is handled explicitly: 0 * inf would be NaN.
vec2 intersectAabb(vec3 o, vec3 d, vec3 bmin, vec3 bmax, float tMin) {
  float t0 = tMin, t1 = 3.402823466e38;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (o[k] < bmin[k] || o[k] > bmax[k]) return vec2(-1.0);
    } else {
      float inv = 1.0 / d[k];
      float ta = (bmin[k] - o[k]) * inv, tb = (bmax[k] - o[k]) * inv;
      t0 = max(t0, min(ta, tb));
      t1 = min(t1, max(ta, tb));
    }
  }
  return t0 <= t1 ? vec2(t0, t1) : vec2(-1.0);
}

#endif

// Camera in the nerf_synthetic / OpenGL convention: the camera looks down -Z, +Y is up, +X right;
// image rows grow downwards. Lens distortion in OpenCV's conventions (vknerf/camera.h), undistorted
// here exactly as src/core/camera/lens.h does. Layout mirrors vknerf::nerf::CameraGpu
// (src/nerf/rays/rays.h).
#ifndef VKNERF_CAMERA_GLSL
#define VKNERF_CAMERA_GLSL

struct Camera {
  vec4 intrinsics;  // fx, fy, cx, cy (pixels)
  vec4 c2w[3];      // rows of the 3x4 camera-to-world matrix
  uvec4 size;       // width, height, first pixel of this image in its pixel binding, that binding's index
  vec4 lensK;       // k1, k2, k3, k4
  vec4 lensKP;      // k5, k6, p1, p2
  uvec4 lensModel;  // x: 0 pinhole, 1 OpenCV radial-tangential, 2 OpenCV fisheye; yzw unused
};

const uint kLensOpenCV = 1u;
const uint kLensFisheye = 2u;
// ref::kLensNewtonSteps: checkLens() proves at load that this many steps converge over the image.
const int kLensNewtonSteps = 20;
const float kLensSingular = 1e-12;
const float kLensLargest = 1e18;  // ref::kLensLargest

// distort() of the OpenCV model at p (residual against pd) and its Jacobian, as ref::opencvJacobian.
vec2 opencvDistort(Camera cam, vec2 p, out mat2 J) {
  vec4 k = cam.lensK, kp = cam.lensKP;
  float r2 = dot(p, p);
  float a = 1.0 + r2 * (k.x + r2 * (k.y + r2 * k.z));
  float b = 1.0 + r2 * (k.w + r2 * (kp.x + r2 * kp.y));
  float da = k.x + r2 * (2.0 * k.y + r2 * 3.0 * k.z);
  float db = k.w + r2 * (2.0 * kp.x + r2 * 3.0 * kp.y);
  float radial = a / b, dRadial = (da * b - a * db) / (b * b);
  float p1 = kp.z, p2 = kp.w;
  float cross = 2.0 * p.x * p.y * dRadial + 2.0 * p1 * p.x + 2.0 * p2 * p.y;
  // Column-major: J[0] = d/dx, J[1] = d/dy.
  J = mat2(radial + 2.0 * p.x * p.x * dRadial + 2.0 * p1 * p.y + 6.0 * p2 * p.x, cross,
           cross, radial + 2.0 * p.y * p.y * dRadial + 6.0 * p1 * p.y + 2.0 * p2 * p.x);
  return vec2(p.x * radial + 2.0 * p1 * p.x * p.y + p2 * (r2 + 2.0 * p.x * p.x),
              p.y * radial + p1 * (r2 + 2.0 * p.y * p.y) + 2.0 * p2 * p.x * p.y);
}

// Direction (not normalised) through the distorted normalised point pd in the OpenCV camera frame
// (x right, y down, z forward): ref::lensDirection. Fixed step counts, no early exit.
vec3 lensDirection(Camera cam, vec2 pd) {
  vec3 d = vec3(pd, 1.0);
  if (cam.lensModel.x == kLensOpenCV) {
    vec2 p = pd;
    for (int i = 0; i < kLensNewtonSteps; ++i) {
      mat2 J;
      vec2 e = opencvDistort(cam, p, J) - pd;
      float det = J[0][0] * J[1][1] - J[1][0] * J[0][1];
      vec2 step = vec2(e.x * J[1][1] - e.y * J[1][0], e.y * J[0][0] - e.x * J[0][1]) / det;
      p -= abs(det) > kLensSingular ? step : vec2(0.0);
    }
    d = vec3(p, 1.0);
  } else if (cam.lensModel.x == kLensFisheye) {
    vec4 k = cam.lensK;
    float rd = length(pd), theta = rd;
    for (int i = 0; i < kLensNewtonSteps; ++i) {
      float t2 = theta * theta;
      float thetaD = theta * (1.0 + t2 * (k.x + t2 * (k.y + t2 * (k.z + t2 * k.w))));
      float dThetaD = 1.0 + t2 * (3.0 * k.x + t2 * (5.0 * k.y + t2 * (7.0 * k.z + t2 * 9.0 * k.w)));
      theta -= abs(dThetaD) > kLensSingular ? (thetaD - rd) / dThetaD : 0.0;
    }
    theta = clamp(theta, 0.0, 1.5707963267948966);
    float s = rd > 0.0 ? sin(theta) / rd : 1.0;
    d = vec3(pd * s, cos(theta));
  }
  // A lens checkLens() would reject must still not make NaN rays: a non-finite or absurd result
  // (whose rotation into the world could overflow) falls back to the pinhole ray.
  if (!all(lessThan(abs(d), vec3(kLensLargest)))) d = vec3(pd, 1.0);
  return d;
}

// Ray through the centre of pixel (x, y): origin and unit direction in world space.
void cameraRay(Camera cam, uint x, uint y, out vec3 origin, out vec3 dir) {
  vec2 pd = (vec2(float(x), float(y)) + 0.5 - cam.intrinsics.zw) / cam.intrinsics.xy;
  vec3 u = lensDirection(cam, pd);
  vec3 dc = vec3(u.x, -u.y, -u.z);
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

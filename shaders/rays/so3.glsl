// Rotations from a rotation vector w (axis * angle): the exponential map and its left Jacobian,
// which camera refinement uses (shaders/rays/camera_correct.comp, camera_gradient.comp). Both as
// src/core/camera/pose_algebra.h; near w = 0 the coefficients come from their series, so a
// correction of zero is the identity exactly and no 0/0 appears.
#ifndef VKNERF_SO3_GLSL
#define VKNERF_SO3_GLSL

mat3 so3Hat(vec3 w) {  // [w]x: so3Hat(w) * v = cross(w, v); column-major
  return mat3(0.0, w.z, -w.y, -w.z, 0.0, w.x, w.y, -w.x, 0.0);
}

// Coefficients a = sin t / t, b = (1 - cos t) / t^2, c = (t - sin t) / t^3 of t = |w|.
vec3 so3Coefficients(vec3 w) {
  float t2 = dot(w, w);
  if (t2 < 1e-6) return vec3(1.0 - t2 / 6.0, 0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0);
  float t = sqrt(t2);
  return vec3(sin(t) / t, (1.0 - cos(t)) / t2, (t - sin(t)) / (t2 * t));
}

mat3 so3Exp(vec3 w) {  // I + a K + b K^2
  vec3 k = so3Coefficients(w);
  mat3 K = so3Hat(w);
  return mat3(1.0) + k.x * K + k.y * (K * K);
}

// J_l(w) = I + b K + c K^2: d(exp(w) v) / dw = -[exp(w) v]x J_l(w).
mat3 so3LeftJacobian(vec3 w) {
  vec3 k = so3Coefficients(w);
  mat3 K = so3Hat(w);
  return mat3(1.0) + k.y * K + k.z * (K * K);
}

#endif

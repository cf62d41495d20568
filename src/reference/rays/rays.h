#pragma once
// CPU reference for shaders/rays/rays.comp and camera.glsl, in float or double; the lens in lens.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "reference/rays/lens.h"
#include "vknerf/camera.h"

namespace vknerf::ref {

template <class T> struct Ray {
  std::array<T, 3> o, d;
  T tNear = -1, tFar = -1;  // (-1, -1): the ray misses the box
  bool hit() const { return tNear >= 0; }
};

// Ray through the point (px, py) of the image in pixel coordinates (origin at the top-left corner
// of the top-left pixel): distorted normalised OpenCV coordinates ((px - cx) / fx, (py - cy) / fy),
// undistorted by the lens, become the direction (x, -y, -z) in the OpenGL camera frame, then world.
template <class T>
Ray<T> cameraRayAt(const Camera& cam, T px, T py) {
  const auto& m = cam.c2w;
  const auto u = lensDirection<T>(cam.lens, (px - T(cam.cx)) / T(cam.fx), (py - T(cam.cy)) / T(cam.fy));
  T dc[3] = {u[0], -u[1], -u[2]};
  Ray<T> r;
  T n = 0;
  for (int k = 0; k < 3; ++k) {
    r.d[k] = T(m[4 * k]) * dc[0] + T(m[4 * k + 1]) * dc[1] + T(m[4 * k + 2]) * dc[2];
    r.o[k] = T(m[4 * k + 3]);
    n += r.d[k] * r.d[k];
  }
  n = std::sqrt(n);
  for (auto& v : r.d) v /= n;
  return r;
}

// Ray through the centre of pixel (x, y).
template <class T>
Ray<T> cameraRay(const Camera& cam, uint32_t x, uint32_t y) {
  return cameraRayAt<T>(cam, T(x) + T(0.5), T(y) + T(0.5));
}

// Slab intersection clipped to t >= tMin; a zero direction component is a slab of infinite extent
// (or a miss when the origin lies outside it), never 0 * inf.
template <class T>
void intersectAabb(Ray<T>& r, const Aabb& box, T tMin) {
  T t0 = tMin, t1 = std::numeric_limits<float>::max();
  for (int k = 0; k < 3; ++k) {
    if (r.d[k] == T(0)) {
      if (r.o[k] < T(box.min[k]) || r.o[k] > T(box.max[k])) {
        r.tNear = r.tFar = -1;
        return;
      }
    } else {
      T inv = T(1) / r.d[k];
      T ta = (T(box.min[k]) - r.o[k]) * inv, tb = (T(box.max[k]) - r.o[k]) * inv;
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    }
  }
  if (t0 <= t1) {
    r.tNear = t0;
    r.tFar = t1;
  } else {
    r.tNear = r.tFar = -1;
  }
}

}  // namespace vknerf::ref

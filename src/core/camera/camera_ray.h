#pragma once
// A camera's ray through a point of its image, in float or double: the host's twin of
// shaders/rays/rays.comp and camera.glsl (point clouds place their points with it, the tests take it
// as the reference); the lens in lens.h.
#include <array>
#include <cmath>
#include <cstdint>

#include "core/camera/lens.h"
#include "vknerf/camera.h"

namespace vknerf::core {

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

}  // namespace vknerf::core

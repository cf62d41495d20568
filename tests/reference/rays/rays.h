#pragma once
// CPU reference for shaders/rays/rays.comp and camera.glsl, in float or double: a camera's ray is
// production's (src/core/camera/camera_ray.h), the box it crosses the oracle's; the lens in lens.h.
#include <algorithm>
#include <limits>

#include "core/camera/camera_ray.h"
#include "reference/rays/lens.h"
#include "vknerf/camera.h"

namespace vknerf::ref {

using core::cameraRay;
using core::cameraRayAt;
using core::Ray;

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

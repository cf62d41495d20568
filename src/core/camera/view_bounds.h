#pragma once
// Which occupancy cells some training camera sees (instant-ngp's mark_untrained_density_grid), as a
// pinhole bound that holds the lens: per camera, the world-to-camera transform (OpenCV frame: x
// right, y down, z forward) and the rectangle of undistorted normalised coordinates (x/z, y/z) that
// contains the ray of every pixel of its image. shaders/occupancy/occupancy_mark_unseen.comp mirrors
// pointSeen() step for step in float; the cells and their corners are the oracle's
// (tests/reference/occupancy/view_bounds.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "core/camera/lens.h"
#include "vknerf/camera.h"

namespace vknerf::core {

// 16 floats, the shader's `ViewBound` (std430): three rows (rotation, translation) and the bounds.
struct ViewBound {
  std::array<float, 4> row[3];
  float xMin, xMax, yMin, yMax;
};
static_assert(sizeof(ViewBound) == 64);

// Rays with a z component below this (relative to their length) leave the pinhole bound unbounded.
inline constexpr double kViewNearlySideways = 1e-6;
inline constexpr float kViewUnbounded = 1e30f;

// Undistorted normalised direction (x/z, y/z) of pixel position (u, v) (pixel edges at integers),
// through the lens; false when the ray points sideways or backwards.
inline bool pixelTangents(const Camera& c, double u, double v, double& x, double& y) {
  const auto d = lensDirection(c.lens, (u - c.cx) / c.fx, (v - c.cy) / c.fy);
  const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(d[2] > kViewNearlySideways * n)) return false;
  x = d[0] / d[2];
  y = d[1] / d[2];
  return true;
}

inline ViewBound viewBoundOf(const Camera& c) {
  ViewBound b{};
  // c2w is OpenGL (x right, y up, looking down -z): the OpenCV camera axes in the world are its
  // columns x, -y, -z; world -> camera is their transpose applied to p - origin.
  const double o[3] = {c.c2w[3], c.c2w[7], c.c2w[11]};
  const double sign[3] = {1, -1, -1};
  for (int r = 0; r < 3; ++r) {
    double t = 0;
    for (int k = 0; k < 3; ++k) {
      const double a = sign[r] * c.c2w[k * 4 + r];
      b.row[r][k] = float(a);
      t -= a * o[k];
    }
    b.row[r][3] = float(t);
  }
  // The image border maps onto the border of what the lens sees (checkLens: the map is monotonic
  // over the image), so the border's tangents bound every pixel's; sampled densely, padded by 1%.
  constexpr int kPerEdge = 64;
  double xMin = 1e300, xMax = -1e300, yMin = 1e300, yMax = -1e300;
  bool bounded = true;
  const double w = c.width, h = c.height;
  for (int i = 0; i <= kPerEdge && bounded; ++i) {
    const double s = double(i) / kPerEdge;
    const double edge[4][2] = {{s * w, 0}, {s * w, h}, {0, s * h}, {w, s * h}};
    for (const auto& p : edge) {
      double x, y;
      if (!pixelTangents(c, p[0], p[1], x, y)) {
        bounded = false;
        break;
      }
      xMin = std::min(xMin, x), xMax = std::max(xMax, x), yMin = std::min(yMin, y), yMax = std::max(yMax, y);
    }
  }
  if (!bounded) {
    b.xMin = b.yMin = -kViewUnbounded;
    b.xMax = b.yMax = kViewUnbounded;
    return b;
  }
  const double px = 0.01 * (xMax - xMin), py = 0.01 * (yMax - yMin);
  b.xMin = float(xMin - px), b.xMax = float(xMax + px), b.yMin = float(yMin - py), b.yMax = float(yMax + py);
  return b;
}

inline std::vector<ViewBound> viewBoundsOf(std::span<const Camera> cameras) {
  std::vector<ViewBound> out;
  out.reserve(cameras.size());
  for (const Camera& c : cameras) out.push_back(viewBoundOf(c));
  return out;
}

// World point p in front of the camera and inside its bound (float, the shader's order).
inline bool pointSeen(const ViewBound& b, const std::array<float, 3>& p) {
  float q[3];
  for (int r = 0; r < 3; ++r) q[r] = b.row[r][0] * p[0] + b.row[r][1] * p[1] + b.row[r][2] * p[2] + b.row[r][3];
  return q[2] > 0.0f && q[0] >= b.xMin * q[2] && q[0] <= b.xMax * q[2] && q[1] >= b.yMin * q[2] && q[1] <= b.yMax * q[2];
}

}  // namespace vknerf::core

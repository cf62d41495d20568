// Scene boxes: from where the cameras look, then carved by alpha masks; or the hull of the cameras'
// frustums between the depth bounds a file states.
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "io/dataset/dataset_loaders.h"
#include "vknerf/error.h"

namespace vknerf::io::detail {
namespace {

using Vec3 = std::array<double, 3>;

Vec3 origin(const Camera& c) { return {c.c2w[3], c.c2w[7], c.c2w[11]}; }
// The optical axis: the camera looks down its -Z column.
Vec3 axis(const Camera& c) {
  Vec3 d{-c.c2w[2], -c.c2w[6], -c.c2w[10]};
  double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (double& v : d) v /= n;
  return d;
}
double dist(const Vec3& a, const Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

// Solves the symmetric 3x3 system A x = b by Cramer's rule; false when A is singular.
bool solve3(const double A[3][3], const Vec3& b, Vec3& x) {
  auto det = [](const double M[3][3]) {
    return M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
           M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
  };
  double d = det(A);
  if (!(std::fabs(d) > 0) || !std::isfinite(d)) return false;
  for (int k = 0; k < 3; ++k) {
    double M[3][3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) M[r][c] = c == k ? b[r] : A[r][c];
    x[k] = det(M) / d;
  }
  return true;
}

// tan of the wider half field of view: to the farthest image edge from the principal point, through
// the lens (the ray through the middle of each edge; a pinhole's, exactly, from the intrinsics).
double widerHalfFieldTangent(const Camera& c) {
  const float w = float(c.width), h = float(c.height);
  if (c.lens.model == LensModel::Pinhole) return std::max(std::max(c.cx, w - c.cx) / c.fx, std::max(c.cy, h - c.cy) / c.fy);
  double tangent = 0;
  for (auto [x, y] : {std::pair{0.0f, c.cy}, {w, c.cy}, {c.cx, 0.0f}, {c.cx, h}}) {
    const auto d = pixelDirection(c, x, y);
    const double forward = -double(d[2]), sideways = std::hypot(double(d[0]), double(d[1]));
    tangent = std::max(tangent, forward > 1e-6 * sideways ? sideways / forward : 1e6);  // 1e6: beyond 90 degrees
  }
  return tangent;
}

}  // namespace

Aabb boxFromCameras(std::span<const Camera> cameras) {
  if (cameras.empty()) throw Error("cannot place a scene box without cameras");
  const double n = double(cameras.size());
  Vec3 meanO{0, 0, 0}, meanD{0, 0, 0};
  for (const Camera& c : cameras) {
    Vec3 o = origin(c), d = axis(c);
    for (int k = 0; k < 3; ++k) meanO[k] += o[k] / n, meanD[k] += d[k] / n;
  }
  double spread = 0;
  for (const Camera& c : cameras) spread = std::max(spread, dist(origin(c), meanO));
  // The point closest to every optical axis minimises sum |(I - d d^T)(p - o)|^2. Parallel axes
  // (one camera, a forward-facing capture) leave it undetermined along them; a weak pull towards a
  // point in front of the cameras, at a depth of the order of their spread, settles it there.
  double depth = spread > 0 ? spread : 1.0;
  double meanDNorm = std::sqrt(meanD[0] * meanD[0] + meanD[1] * meanD[1] + meanD[2] * meanD[2]);
  Vec3 prior = meanO;
  if (meanDNorm > 0)
    for (int k = 0; k < 3; ++k) prior[k] += meanD[k] / meanDNorm * depth;
  const double lambda = 1e-3 * n;
  double A[3][3] = {{lambda, 0, 0}, {0, lambda, 0}, {0, 0, lambda}};
  Vec3 b{lambda * prior[0], lambda * prior[1], lambda * prior[2]};
  for (const Camera& c : cameras) {
    Vec3 o = origin(c), d = axis(c);
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) {
        double P = (r == k ? 1.0 : 0.0) - d[r] * d[k];
        A[r][k] += P;
        b[r] += P * o[k];
      }
  }
  Vec3 centre = prior;
  solve3(A, b, centre);

  // The half width each camera sees at the centre's distance, over its wider half field of view.
  std::vector<double> halves;
  for (const Camera& c : cameras) halves.push_back(dist(centre, origin(c)) * widerHalfFieldTangent(c));
  std::nth_element(halves.begin(), halves.begin() + halves.size() / 2, halves.end());
  double half = halves[halves.size() / 2];
  if (!(half > 1e-6 * depth) || !std::isfinite(half)) half = depth;  // cameras sitting at the centre
  Aabb box;
  for (int k = 0; k < 3; ++k) {
    box.min[k] = float(centre[k] - half);
    box.max[k] = float(centre[k] + half);
  }
  return box;
}

Aabb cascadedBoxFromDepths(std::span<const Camera> cameras, std::span<const std::array<float, 2>> depthBounds,
                           const Aabb& whole, float& aabbScale) {
  if (cameras.empty() || cameras.size() != depthBounds.size())
    throw Error("a forward-facing box needs one {near, far} per camera and at least one camera");
  const double n = double(cameras.size());
  Vec3 meanO{0, 0, 0}, meanD{0, 0, 0};
  std::vector<double> nears;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Vec3 o = origin(cameras[i]), d = axis(cameras[i]);
    for (int k = 0; k < 3; ++k) meanO[k] += o[k] / n, meanD[k] += d[k] / n;
    nears.push_back(depthBounds[i][0]);
  }
  const double norm = std::sqrt(meanD[0] * meanD[0] + meanD[1] * meanD[1] + meanD[2] * meanD[2]);
  if (!(norm > 1e-6)) throw Error("a forward-facing box needs cameras that look the same way on the whole");
  std::nth_element(nears.begin(), nears.begin() + nears.size() / 2, nears.end());
  const double depth = 1.5 * nears[nears.size() / 2];
  Vec3 centre;
  for (int k = 0; k < 3; ++k) centre[k] = meanO[k] + meanD[k] / norm * depth;
  // Each camera's frame at that depth: the corners where the rays through its image corners reach it.
  double half = 0.5 * depth;
  for (const Camera& c : cameras) {
    const auto& m = c.c2w;
    const Vec3 o = origin(c), d = axis(c);
    const double z = (centre[0] - o[0]) * d[0] + (centre[1] - o[1]) * d[1] + (centre[2] - o[2]) * d[2];
    for (double u : {0.0, double(c.width)})
      for (double v : {0.0, double(c.height)}) {
        const double p[3] = {z * (u - c.cx) / c.fx, -z * (v - c.cy) / c.fy, -z};
        for (int k = 0; k < 3; ++k)
          half = std::max(half, std::fabs(m[4 * k] * p[0] + m[4 * k + 1] * p[1] + m[4 * k + 2] * p[2] + m[4 * k + 3] - centre[k]));
      }
  }
  constexpr float kMaxScale = 128;  // 8 cascades, as TrainConfig::validate allows
  double reach = 0;
  for (int k = 0; k < 3; ++k) reach = std::max({reach, centre[k] - whole.min[k], whole.max[k] - centre[k]});
  aabbScale = 1;
  while (aabbScale < kMaxScale && half * aabbScale < reach) aabbScale *= 2;
  Aabb box;
  for (int k = 0; k < 3; ++k) {
    box.min[k] = float(centre[k] - half * aabbScale);
    box.max[k] = float(centre[k] + half * aabbScale);
  }
  return box;
}

Aabb boxFromFrustums(std::span<const Camera> cameras, std::span<const std::array<float, 2>> depthBounds) {
  if (cameras.empty() || cameras.size() != depthBounds.size())
    throw Error("a frustum box needs one {near, far} per camera and at least one camera");
  const double inf = std::numeric_limits<double>::infinity();
  Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Camera& c = cameras[i];
    if (c.lens.model != LensModel::Pinhole) throw Error("a frustum box is for pinhole cameras");
    const auto& m = c.c2w;
    // The ray through pixel position (u, v) reaches depth z at z * ((u - cx) / fx, -(v - cy) / fy, -1)
    // in the camera's frame; the frustum between two depths is the hull of those eight corners.
    for (double z : depthBounds[i])
      for (double u : {0.0, double(c.width)})
        for (double v : {0.0, double(c.height)}) {
          const double p[3] = {z * (u - c.cx) / c.fx, -z * (v - c.cy) / c.fy, -z};
          for (int k = 0; k < 3; ++k) {
            const double w = m[4 * k] * p[0] + m[4 * k + 1] * p[1] + m[4 * k + 2] * p[2] + m[4 * k + 3];
            lo[k] = std::min(lo[k], w);
            hi[k] = std::max(hi[k], w);
          }
        }
  }
  // Rounded outwards to floats, so that every corner lies inside the box.
  Aabb box;
  for (int k = 0; k < 3; ++k) {
    box.min[k] = float(lo[k]);
    if (double(box.min[k]) > lo[k]) box.min[k] = std::nextafter(box.min[k], -std::numeric_limits<float>::infinity());
    box.max[k] = float(hi[k]);
    if (double(box.max[k]) < hi[k]) box.max[k] = std::nextafter(box.max[k], std::numeric_limits<float>::infinity());
  }
  return box;
}

bool carveWithAlpha(std::span<const Camera> cameras, std::span<const ImageRGBA8> images, Aabb& box) {
  bool anyTransparent = false;
  for (const ImageRGBA8& img : images)
    for (size_t i = 3; i < img.rgba.size() && !anyTransparent; i += 4) anyTransparent = img.rgba[i] == 0;
  if (!anyTransparent) return false;
  for (const Camera& c : cameras)
    if (c.lens.model != LensModel::Pinhole) return false;  // the projection below is the pinhole's

  // Only the given box is searched: a larger region would reach the cameras, and the space between
  // a camera and the object is seen through the object by that camera and hardly by any other, so
  // it would survive and inflate the box.
  constexpr int kRes = 64;
  double lo[3], cell[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = box.min[k];
    cell[k] = (double(box.max[k]) - box.min[k]) / kRes;
  }
  const double radius = 0.5 * std::sqrt(cell[0] * cell[0] + cell[1] * cell[1] + cell[2] * cell[2]);
  // Per cell: kAlive until some mask rules it out, kSeen once a camera has its centre in view; a cell
  // no camera sees cannot be reconstructed and is not kept.
  constexpr uint8_t kAlive = 1, kSeen = 2;
  std::vector<uint8_t> state(size_t(kRes) * kRes * kRes, kAlive);
  std::vector<uint32_t> sat;  // summed-area table of (alpha > 0), (w + 1) x (h + 1)

  for (size_t ci = 0; ci < cameras.size(); ++ci) {
    const Camera& cam = cameras[ci];
    const ImageRGBA8& img = images[ci];
    const uint32_t w = img.width, h = img.height;
    sat.assign(size_t(w + 1) * (h + 1), 0);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x)
        sat[size_t(y + 1) * (w + 1) + x + 1] = (img.rgba[(size_t(y) * w + x) * 4 + 3] > 0) + sat[size_t(y) * (w + 1) + x + 1] +
                                               sat[size_t(y + 1) * (w + 1) + x] - sat[size_t(y) * (w + 1) + x];
    const auto& m = cam.c2w;
    for (int iz = 0; iz < kRes; ++iz)
      for (int iy = 0; iy < kRes; ++iy)
        for (int ix = 0; ix < kRes; ++ix) {
          uint8_t& a = state[(size_t(iz) * kRes + iy) * kRes + ix];
          if (!(a & kAlive)) continue;
          double q[3] = {lo[0] + (ix + 0.5) * cell[0] - m[3], lo[1] + (iy + 0.5) * cell[1] - m[7],
                         lo[2] + (iz + 0.5) * cell[2] - m[11]};
          // Camera coordinates (R^T q); depth is along -Z.
          double vx = m[0] * q[0] + m[4] * q[1] + m[8] * q[2];
          double vy = m[1] * q[0] + m[5] * q[1] + m[9] * q[2];
          double z = -(m[2] * q[0] + m[6] * q[1] + m[10] * q[2]);
          if (z <= 0) continue;
          double u = cam.cx + cam.fx * vx / z, v = cam.cy - cam.fy * vy / z;
          if (!(u >= 0 && v >= 0 && u < w && v < h)) continue;  // out of view: no constraint
          a |= kSeen;
          if (z - radius <= 1e-9) continue;  // the cell reaches behind the camera: no constraint
          // Any point within `radius` of the centre projects within f r (1 + |v/z|) / (z - r).
          double ru = cam.fx * radius * (1 + std::fabs(vx / z)) / (z - radius);
          double rv = cam.fy * radius * (1 + std::fabs(vy / z)) / (z - radius);
          // The window is clipped to the image: what lies beyond the frame is taken to be as empty as the
          // frame's edge, which holds for objects fully in view (the case alpha masks come from).
          size_t X0 = size_t(std::max(0.0, std::floor(u - ru))), X1 = size_t(std::min(double(w - 1), std::floor(u + ru))) + 1;
          size_t Y0 = size_t(std::max(0.0, std::floor(v - rv))), Y1 = size_t(std::min(double(h - 1), std::floor(v + rv))) + 1;
          uint32_t covered = sat[Y1 * (w + 1) + X1] - sat[Y0 * (w + 1) + X1] - sat[Y1 * (w + 1) + X0] + sat[Y0 * (w + 1) + X0];
          if (covered == 0) a = 0;  // every point of the cell projects onto transparent pixels
        }
  }

  Aabb carved;
  bool any = false;
  for (int iz = 0; iz < kRes; ++iz)
    for (int iy = 0; iy < kRes; ++iy)
      for (int ix = 0; ix < kRes; ++ix) {
        if (state[(size_t(iz) * kRes + iy) * kRes + ix] != (kAlive | kSeen)) continue;
        int idx[3] = {ix, iy, iz};
        for (int k = 0; k < 3; ++k) {
          float a = float(lo[k] + idx[k] * cell[k]), b = float(lo[k] + (idx[k] + 1) * cell[k]);
          carved.min[k] = any ? std::min(carved.min[k], a) : a;
          carved.max[k] = any ? std::max(carved.max[k], b) : b;
        }
        any = true;
      }
  if (!any) return false;
  box = carved;
  return true;
}

}  // namespace vknerf::io::detail

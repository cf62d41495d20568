// The public camera builders (include/vknerf/camera.h): look-at frames, orbit poses and pinhole
// intrinsics, checked through the rays the CPU reference casts from them.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "reference/rays/rays.h"
#include "vknerf/camera.h"

using namespace vknerf;

namespace {

using Vec3 = std::array<double, 3>;

constexpr double kTol = 1e-6;  // float rounding of unit vectors, with margin

Vec3 column(const std::array<float, 16>& m, int c) { return {m[c], m[4 + c], m[8 + c]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 unitFromTo(const Vec3& from, const Vec3& to) {
  Vec3 d{to[0] - from[0], to[1] - from[1], to[2] - from[2]};
  const double n = std::sqrt(dot(d, d));
  return {d[0] / n, d[1] / n, d[2] / n};
}

// Right, up and back columns orthonormal and right-handed (right x up = back), last row 0 0 0 1.
void expectRigid(const std::array<float, 16>& m) {
  const Vec3 x = column(m, 0), y = column(m, 1), z = column(m, 2);
  EXPECT_NEAR(dot(x, x), 1, kTol);
  EXPECT_NEAR(dot(y, y), 1, kTol);
  EXPECT_NEAR(dot(z, z), 1, kTol);
  EXPECT_NEAR(dot(x, y), 0, kTol);
  EXPECT_NEAR(dot(y, z), 0, kTol);
  EXPECT_NEAR(dot(z, x), 0, kTol);
  const Vec3 xy{x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(xy[k], z[k], kTol);
  EXPECT_EQ(m[12], 0.0f);
  EXPECT_EQ(m[13], 0.0f);
  EXPECT_EQ(m[14], 0.0f);
  EXPECT_EQ(m[15], 1.0f);
}

}  // namespace

TEST(Camera, LookAtLooksFromTheEyeAtTheTarget) {
  const Vec3 eye{2.4, 0.9, 2.1}, target{0.5, -0.25, 0.1};
  for (std::array<float, 3> up : {std::array<float, 3>{0, 1, 0}, {0, 0, 1}, {0, 0, 3}}) {
    const auto m = lookAt({2.4f, 0.9f, 2.1f}, {0.5f, -0.25f, 0.1f}, up);
    expectRigid(m);
    const Vec3 forward = unitFromTo(eye, target), back = column(m, 2);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(-back[k], forward[k], kTol) << "the camera's -Z must point from eye to target";
      EXPECT_EQ(m[4 * k + 3], float(eye[k])) << "the camera sits at the eye";
    }
    // Image up leans towards the world's up, and the image's right is level with respect to it.
    const Vec3 worldUp{up[0], up[1], up[2]};
    EXPECT_GT(dot(column(m, 1), worldUp), 0);
    EXPECT_NEAR(dot(column(m, 0), worldUp), 0, kTol * 3);
  }
}

TEST(Camera, PinholeIntrinsicsFromFovAndFocal) {
  const auto pose = lookAt({0, 0, 3}, {0, 0, 0}, {0, 1, 0});
  const Camera a = pinholeFromFov(40, 30, 90, pose);
  EXPECT_NEAR(a.fx, 20.0f, 1e-5f);  // tan(45 degrees) = 1: the half width
  EXPECT_EQ(a.fy, a.fx);
  EXPECT_EQ(a.cx, 20.0f);
  EXPECT_EQ(a.cy, 15.0f);
  EXPECT_EQ(a.width, 40u);
  EXPECT_EQ(a.height, 30u);
  EXPECT_EQ(a.c2w, pose);
  const Camera b = pinholeFromFocal(16, 12, 19.2f, pose);
  EXPECT_EQ(b.fx, 19.2f);
  EXPECT_EQ(b.fy, 19.2f);
  EXPECT_EQ(b.cx, 8.0f);
  EXPECT_EQ(b.cy, 6.0f);
}

TEST(Camera, KnownPixelsMapToKnownRays) {
  // 5x5 pixels, 90 degrees: the centre pixel's ray goes to the target; the middle pixel of the
  // left column is 2 pixels of a 2.5 pixel focal length to the left, and the top row's is as far up.
  const Vec3 eye{3, 1, 2}, target{0, 1, 0};
  const Camera cam = pinholeFromFov(5, 5, 90, lookAt({3, 1, 2}, {0, 1, 0}, {0, 1, 0}));
  const auto centre = ref::cameraRay<double>(cam, 2, 2);
  const Vec3 forward = unitFromTo(eye, target);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(centre.o[k], eye[k], kTol);
    EXPECT_NEAR(centre.d[k], forward[k], kTol);
  }
  const Vec3 right = column(cam.c2w, 0), up = column(cam.c2w, 1);
  // Level with y = 1 (+Y world up): right is horizontal, so the left pixel's ray stays at y = 1.
  const auto left = ref::cameraRay<double>(cam, 0, 2), top = ref::cameraRay<double>(cam, 2, 0);
  const double len = std::sqrt(1 + 0.8 * 0.8);  // (-0.8, 0, -1) in camera space
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(left.d[k], (forward[k] - 0.8 * right[k]) / len, kTol);
    EXPECT_NEAR(top.d[k], (forward[k] + 0.8 * up[k]) / len, kTol);
  }
  EXPECT_NEAR(left.d[1], 0, kTol);
  EXPECT_GT(top.d[1], 0) << "row 0 is the top of the image";
}

TEST(Camera, OrbitPosesCircleTheCentreWithZUp) {
  const std::array<float, 3> c{0.5f, -0.25f, 0.1f};
  const Vec3 centre{c[0], c[1], c[2]};
  const float radius = 4, elevation = 30;
  const uint32_t count = 8;
  for (uint32_t i = 0; i < count; ++i) {
    const auto m = orbitPose(c, radius, elevation, i, count);
    expectRigid(m);
    const Vec3 pos{m[3], m[7], m[11]};
    const double az = 2 * M_PI * i / count, el = elevation * M_PI / 180;
    const Vec3 expected{c[0] + radius * std::cos(el) * std::cos(az), c[1] + radius * std::cos(el) * std::sin(az),
                        c[2] + radius * std::sin(el)};
    // Positions are floats of magnitude ~4: a few of their ulps (4.8e-7) are well inside 1e-5.
    const Vec3 offset{pos[0] - centre[0], pos[1] - centre[1], pos[2] - centre[2]};
    EXPECT_NEAR(std::sqrt(dot(offset, offset)), radius, 1e-5) << "camera " << i;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(pos[k], expected[k], 1e-5) << "camera " << i;
    const Vec3 forward = unitFromTo(pos, centre), back = column(m, 2);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(-back[k], forward[k], kTol) << "camera " << i;
    EXPECT_EQ(m[8], 0.0f) << "the image's right is horizontal (z component of the right axis)";
    EXPECT_GT(m[9], 0) << "the image's up points up the world's +Z";
  }
}

// Lens distortion: the lens math (src/core/camera/lens.h) inverts every model over the whole
// image, rays through distorted pixels hit the points that project there, checkLens refuses lenses
// that do not invert, and rays.comp matches the reference with a lens.
#include <cmath>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/rays/rays.h"
#include "reference/rays/lens.h"
#include "reference/rays/rays.h"
#include "support/error_message.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"

using namespace vknerf;
using vknerf::test::errorOf;

namespace {

// A 640x480 camera at `eye` looking at the origin (+Z up) with `lens`, the principal point a little
// off centre, as calibrated cameras have it.
Camera lensCamera(const Lens& lens, float focal, std::array<float, 3> eye = {3, 1, 1.5f}) {
  Camera c = pinholeFromFocal(640, 480, focal, lookAt(eye, {0, 0, 0}, {0, 0, 1}));
  c.cx = 325.5f;
  c.cy = 236.25f;
  c.fy = focal * 1.01f;
  c.lens = lens;
  return c;
}

// The solution v of R v = q for the rotation part R of the row-major 4x4 `m`, by Cramer's rule.
std::array<double, 3> solve(const std::array<float, 16>& m, const double q[3]) {
  auto det = [&](int replaced) {
    double a[3][3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a[r][c] = c == replaced ? q[r] : double(m[4 * r + c]);
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  };
  const double d = det(-1);
  return {det(0) / d, det(1) / d, det(2) / d};
}

struct NamedCamera {
  const char* name;
  Camera camera;
};

// One camera per model, with coefficients of the size real calibrations have.
std::vector<NamedCamera> distortedCameras() {
  Lens phone{LensModel::OpenCV, -0.28f, 0.09f, -0.012f, 0, 0, 0, 8e-4f, -5e-4f};  // COLMAP OPENCV + k3
  Lens rational{LensModel::OpenCV, 0.6f, -0.1f, 0.02f, 0.9f, -0.05f, 0.01f, 2e-4f, 1e-4f};  // FULL_OPENCV
  Lens pincushion{LensModel::OpenCV, 0.15f, 0.02f};                                          // RADIAL
  Lens fisheye{LensModel::Fisheye, 0.03f, -0.006f, 0.001f, -2e-4f};                          // OPENCV_FISHEYE
  Lens strongFisheye{LensModel::Fisheye, -0.05f};  // SIMPLE_RADIAL_FISHEYE, ~160 degrees across
  return {{"phone", lensCamera(phone, 500)},
          {"rational", lensCamera(rational, 450)},
          {"pincushion", lensCamera(pincushion, 520)},
          {"fisheye", lensCamera(fisheye, 260)},
          {"strong fisheye", lensCamera(strongFisheye, 330)}};
}

}  // namespace

// Both directions on a 33 x 33 grid of pixel positions from edge to edge (corners included): the
// distorted point p comes back from undistort then distort, and q = undistort(p) comes back from
// distort then undistort. Double precision Newton converges quadratically to ~1e-16; 1e-10 in
// normalised units (1e-7 pixel at f = 500) leaves room for the conditioning at the corners.
TEST(Lens, UndistortDistortRoundTripsOverTheWholeImage) {
  constexpr int kGrid = 32;
  for (const auto& [name, c] : distortedCameras()) {
    EXPECT_NO_THROW(checkLens(c, name)) << name;
    for (int iy = 0; iy <= kGrid; ++iy)
      for (int ix = 0; ix <= kGrid; ++ix) {
        const double xd = (c.width * double(ix) / kGrid - c.cx) / c.fx;
        const double yd = (c.height * double(iy) / kGrid - c.cy) / c.fy;
        const auto q = ref::undistort(c.lens, xd, yd);
        const auto p = ref::distort(c.lens, q.x, q.y);
        ASSERT_NEAR(p.x, xd, 1e-10) << name << " at grid (" << ix << ", " << iy << ")";
        ASSERT_NEAR(p.y, yd, 1e-10) << name << " at grid (" << ix << ", " << iy << ")";
        const auto q2 = ref::undistort(c.lens, p.x, p.y);
        ASSERT_NEAR(q2.x, q.x, 1e-10 * (1 + std::fabs(q.x))) << name;
        ASSERT_NEAR(q2.y, q.y, 1e-10 * (1 + std::fabs(q.y))) << name;
        if (ix == 0 && iy == 0) {  // the lens really distorts the corner (by more than a pixel)
          EXPECT_GT(std::hypot(q.x - xd, q.y - yd) * c.fx, 1.0) << name;
        }
      }
  }
}

TEST(Lens, PinholeIsTheIdentity) {
  const Lens pinhole;
  const auto d = ref::distort(pinhole, 0.3, -0.2);
  const auto u = ref::undistort(pinhole, 0.3, -0.2);
  EXPECT_EQ(d.x, 0.3);
  EXPECT_EQ(d.y, -0.2);
  EXPECT_EQ(u.x, 0.3);
  EXPECT_EQ(u.y, -0.2);
}

// Project world points through the full forward model (world -> OpenCV camera frame -> normalised
// -> distort -> pixel), then generate the reference ray at that sub-pixel position: it must pass
// through the point. The distance is relative to the point's depth; 1e-9 is double rounding through
// a converged Newton solve.
TEST(Lens, RayThroughADistortedPixelHitsThePointThatProjectsThere) {
  for (const auto& [name, c] : distortedCameras()) {
    const auto& m = c.c2w;
    int hits = 0;
    for (int i = -6; i <= 6; ++i)
      for (int j = -6; j <= 6; ++j)
        for (int k = 0; k < 3; ++k) {
          const double P[3] = {0.25 * i, 0.25 * j, 0.4 * (k - 1)};
          const double q[3] = {P[0] - m[3], P[1] - m[7], P[2] - m[11]};
          // OpenGL camera coordinates R^-1 q (the float pose is orthonormal only to ~1e-7, so R^T
          // would not do at this tolerance), then OpenCV's: y and z flipped.
          const auto v0 = solve(m, q);
          const double X = v0[0], Y = -v0[1], Z = -v0[2];
          if (Z <= 0) continue;
          const auto pd = ref::distort(c.lens, X / Z, Y / Z);
          const double px = c.fx * pd.x + c.cx, py = c.fy * pd.y + c.cy;
          if (!(px >= 0 && py >= 0 && px <= c.width && py <= c.height)) continue;
          const auto r = ref::cameraRayAt<double>(c, px, py);
          const double v[3] = {P[0] - r.o[0], P[1] - r.o[1], P[2] - r.o[2]};
          const double t = v[0] * r.d[0] + v[1] * r.d[1] + v[2] * r.d[2];
          ASSERT_GT(t, 0) << name;
          double dist2 = 0;
          for (int a = 0; a < 3; ++a) dist2 += (v[a] - t * r.d[a]) * (v[a] - t * r.d[a]);
          EXPECT_LT(std::sqrt(dist2), 1e-9 * t) << name << " point (" << P[0] << ", " << P[1] << ", " << P[2] << ")";
          ++hits;
        }
    EXPECT_GT(hits, 100) << name;  // the grid covers the view, corners and all
  }
}

TEST(Lens, NonInvertibleLensesAreClearErrors) {
  const std::string invert = "lens distortion does not invert over the image (fails at pixel (";
  Camera c = lensCamera({LensModel::OpenCV, -10}, 500);
  c.cx = 320, c.cy = 240, c.fy = 500;  // every corner equally far: the first, (0, 0), is named
  std::string e = errorOf([&] { checkLens(c, "transforms.json"); });
  EXPECT_MESSAGE_HAS(e, "transforms.json: k1 = -10: " + invert + "0, 0)");
  EXPECT_MESSAGE_HAS(e, "folds back");
  // A rational factor whose denominator outgrows its numerator: the radial map turns back.
  c.lens = {LensModel::OpenCV, 0, 0, 0, 4};
  EXPECT_MESSAGE_HAS(errorOf([&] { checkLens(c, "cam"); }), "cam: k4 = 4: " + invert);
  // Tangential terms strong enough to fold the image over, with a monotonic radial part.
  c.lens = {LensModel::OpenCV, 0, 0, 0, 0, 0, 0, 3, 0};
  EXPECT_MESSAGE_HAS(errorOf([&] { checkLens(c, "cam"); }), "cam: p1 = 3: " + invert);
  // A fisheye whose corners lie beyond 90 degrees, and one whose angle folds back.
  c.lens = {LensModel::Fisheye};
  c.lens.k1 = 1e-6f;
  c.fx = c.fy = 100;
  EXPECT_MESSAGE_HAS(errorOf([&] { checkLens(c, "cam"); }), "90 degrees");
  c.lens = {LensModel::Fisheye, -0.5f};
  c.fx = c.fy = 500;
  EXPECT_MESSAGE_HAS(errorOf([&] { checkLens(c, "cam"); }), "cam: k1 = -0.5: " + invert);
  c.lens = {LensModel::OpenCV, NAN};
  EXPECT_MESSAGE_HAS(errorOf([&] { checkLens(c, "cam"); }), "cam: lens distortion coefficient nan is not finite");
  c.lens = {LensModel(7)};
  EXPECT_MESSAGE_HAS(errorOf([&] { checkLens(c, "cam"); }), "lens model 7 is not a LensModel");
  // packCameras refuses it too, naming the camera, before anything reaches the device.
  std::vector<Camera> cams = {lensCamera({}, 500), lensCamera({LensModel::OpenCV, -10}, 500)};
  EXPECT_MESSAGE_HAS(errorOf([&] { nerf::packCameras(cams); }), "camera 1: k1 = -10: " + invert);
}

namespace {

class LensRays : public test::GpuTest {
 protected:
  // rays.comp over every pixel of camera 0 of `packed`.
  std::vector<float> imageRays(const std::vector<nerf::CameraGpu>& packed, uint32_t count) {
    auto camBuf = gpu::Buffer::of(ctx(), packed);
    gpu::Buffer rays(ctx(), count * nerf::kRayBytes), ids(ctx(), count * nerf::kPixelIdBytes);
    nerf::RayGeneration gen(ctx());
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      gen.recordImage(rec, camBuf, {0, 0, count}, {Aabb{}, 0}, {rays, ids});
    });
    return rays.download<float>(count * 8);
  }
};

}  // namespace

// The shader's float Newton steps against the double reference. Float Newton stops within a few
// ulps of the root: the residual's rounding (~6e-8 of |p|) amplified by the inverse Jacobian (its
// smallest singular value is >= 0.3 over these images) is a few 1e-7 in the unit direction (2.4e-7
// measured at worst). 2e-6, the pinhole rays' tolerance in test_rays.cpp, bounds it with 8x margin.
TEST_F(LensRays, ShaderMatchesTheReference) {
  constexpr double kTol = 2e-6;
  for (const auto& [name, c] : distortedCameras()) {
    const uint32_t n = c.width * c.height;
    auto out = imageRays(nerf::packCameras(std::span<const Camera>(&c, 1)), n);
    for (uint32_t p = 0; p < n; p += 7) {  // every 7th pixel: all rows and columns, corners included below
      const auto r = ref::cameraRay<double>(c, p % c.width, p / c.width);
      for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(test::near(out[8 * p + 4 + k], r.d[k], kTol, kTol)) << name << " pixel " << p;
        ASSERT_TRUE(test::near(out[8 * p + k], r.o[k], kTol, kTol)) << name;
      }
    }
    for (uint32_t p : {0u, c.width - 1, n - c.width, n - 1}) {
      const auto r = ref::cameraRay<double>(c, p % c.width, p / c.width);
      for (int k = 0; k < 3; ++k) EXPECT_TRUE(test::near(out[8 * p + 4 + k], r.d[k], kTol, kTol)) << name << " corner " << p;
    }
  }
}

// A lens checkLens() would refuse, smuggled past packCameras: the shader still writes finite rays.
TEST_F(LensRays, ANonInvertibleLensNeverMakesNaNRays) {
  Camera c = lensCamera({}, 500);
  c.width = 64, c.height = 48, c.cx = 32, c.cy = 24;
  auto packed = nerf::packCameras(std::span<const Camera>(&c, 1));
  for (auto [model, k1, k4] : {std::tuple{LensModel::OpenCV, -10.0f, 0.0f}, {LensModel::OpenCV, 0.0f, -1e4f},
                               {LensModel::Fisheye, -10.0f, 0.0f}}) {
    packed[0].lensModel[0] = uint32_t(model);
    packed[0].lensK[0] = k1;
    packed[0].lensK[3] = k4;
    auto out = imageRays(packed, c.width * c.height);
    for (float v : out) ASSERT_TRUE(std::isfinite(v));
  }
}

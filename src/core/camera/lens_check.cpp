// checkLens (vknerf/camera.h): a lens is usable only where the rays can invert it, so every loader
// and packCameras() prove that over the whole image before a ray is generated.
#include <cmath>
#include <cstdio>

#include "core/camera/lens.h"
#include "vknerf/camera.h"
#include "vknerf/error.h"

namespace vknerf {
namespace {

constexpr double kHalfPi = 1.5707963267948966;
// The grid the round trip is checked on: kGrid + 1 points per side, from one edge of the image to
// the other, so its corners are the image's corners.
constexpr int kGrid = 16;
// distort(undistort(p)) must return p to within a hundredth of a pixel. The check runs in double,
// where converged Newton lands ~1e-12 px away, so anything above this is a lens the fixed step
// count does not invert; yet it is two orders above what the shader's float steps reach (~1e-4 px
// at f = 1000), so a lens that passes here is inverted on the device to well below a pixel.
constexpr double kRoundTripPixels = 0.01;
// The radial sweep's step: 1/512 of the corner's distorted radius (or of the fisheye's 90 degrees),
// fine enough to find a fold of any lens with coefficients of ordinary size.
constexpr int kSweepSteps = 512;

std::string number(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%g", v);
  return s;
}

// "k1 = -10, p2 = 0.001": the coefficients the model uses that are nonzero.
std::string describe(const Lens& l) {
  const bool opencv = l.model == LensModel::OpenCV;
  const std::pair<const char*, float> all[] = {{"k1", l.k1}, {"k2", l.k2}, {"k3", l.k3}, {"k4", l.k4},
                                               {"k5", opencv ? l.k5 : 0}, {"k6", opencv ? l.k6 : 0},
                                               {"p1", opencv ? l.p1 : 0}, {"p2", opencv ? l.p2 : 0}};
  std::string out;
  for (const auto& [name, v] : all)
    if (v != 0) out += (out.empty() ? "" : ", ") + std::string(name) + " = " + number(v);
  return out.empty() ? "no distortion coefficients" : out;
}

// Largest undistorted radius the radial map reaches monotonically before it covers distorted radius
// `rd`; negative when it folds back (or meets a pole) first.
double monotonicRadius(const Lens& l, double rd) {
  if (l.model == LensModel::Fisheye) {
    const double step = kHalfPi / kSweepSteps;
    for (int i = 0; i <= kSweepSteps; ++i) {
      double theta = step * i, thetaD, dThetaD;
      core::fisheyeAngle(l, theta, thetaD, dThetaD);
      if (!(dThetaD > 0)) return -1;
      if (thetaD >= rd) return std::tan(std::fmin(theta, kHalfPi * (1 - 1e-9)));
    }
    return -1;  // the corner lies beyond 90 degrees from the axis: the model cannot reach it
  }
  // OpenCV: g(r) = r radial(r^2) must rise from 0 to rd with a positive denominator. A barrel lens
  // needs r beyond rd, so the sweep runs out to 64 rd before it gives up.
  const double step = rd / kSweepSteps;
  for (int i = 0; i <= 64 * kSweepSteps; ++i) {
    const double r = step * i, r2 = r * r;
    double radial, dRadial;
    core::opencvRadial(l, r2, radial, dRadial);
    if (!(core::opencvRadialDenominator(l, r2) > 0) || !(radial + 2 * r2 * dRadial > 0)) return -1;
    if (r * radial >= rd) return r;
  }
  return -1;
}

}  // namespace

void checkLens(const Camera& cam, const std::string& where) {
  const Lens& l = cam.lens;
  if (l.model != LensModel::Pinhole && l.model != LensModel::OpenCV && l.model != LensModel::Fisheye)
    throw Error(where + ": lens model " + std::to_string(uint32_t(l.model)) + " is not a LensModel");
  for (float v : {l.k1, l.k2, l.k3, l.k4, l.k5, l.k6, l.p1, l.p2})
    if (!std::isfinite(v)) throw Error(where + ": lens distortion coefficient " + number(v) + " is not finite");
  if (l.model == LensModel::Pinhole) return;
  if (!(cam.fx > 0) || !(cam.fy > 0) || !std::isfinite(cam.cx) || !std::isfinite(cam.cy))
    throw Error(where + ": lens distortion needs positive focal lengths and a finite principal point");

  const double fx = cam.fx, fy = cam.fy, cx = cam.cx, cy = cam.cy, w = cam.width, h = cam.height;
  auto fail = [&](double u, double v, const std::string& why) {
    throw Error(where + ": " + describe(l) + ": lens distortion does not invert over the image (fails at pixel (" +
                number(u) + ", " + number(v) + "): " + why + ")");
  };

  // 1. The radial map rises monotonically out to the farthest corner: below the fold Newton has one
  //    root to find, beyond it the photo's corner would have two rays (or none).
  double cornerU = 0, cornerV = 0, rdMax = 0;
  for (double u : {0.0, w})
    for (double v : {0.0, h})
      if (double rd = std::hypot((u - cx) / fx, (v - cy) / fy); rd > rdMax) rdMax = rd, cornerU = u, cornerV = v;
  const double rMax = monotonicRadius(l, rdMax);
  if (rMax < 0)
    fail(cornerU, cornerV,
         l.model == LensModel::Fisheye
             ? "the fisheye angle folds back or the corner lies 90 degrees or more from the optical axis"
             : "the radial distortion folds back or has a pole before the image corner");

  // 2. On a grid reaching the corners, the shader's Newton steps converge to the root below the fold.
  const bool radialOnly = l.model == LensModel::Fisheye || (l.p1 == 0 && l.p2 == 0);
  for (int iy = 0; iy <= kGrid; ++iy)
    for (int ix = 0; ix <= kGrid; ++ix) {
      const double u = w * ix / kGrid, v = h * iy / kGrid;
      const double xd = (u - cx) / fx, yd = (v - cy) / fy;
      const auto p = core::undistort(l, xd, yd);
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) fail(u, v, "the Newton iteration diverges");
      const auto back = core::distort(l, p.x, p.y);
      const double err = std::fmax(std::fabs(back.x - xd) * fx, std::fabs(back.y - yd) * fy);
      if (!(err <= kRoundTripPixels))
        fail(u, v, "distort(undistort(p)) is " + number(err) + " pixels from p after " +
                       std::to_string(core::kLensNewtonSteps) + " Newton steps");
      if (l.model == LensModel::OpenCV) {
        const auto J = core::opencvJacobian(l, p.x, p.y);
        if (!(J[0] * J[3] - J[1] * J[2] > 0)) fail(u, v, "the distortion folds the image over there");
      }
      if (radialOnly && std::hypot(p.x, p.y) > rMax * (1 + 1e-6) + 1e-12)
        fail(u, v, "the Newton iteration lands beyond the fold of the radial distortion");
    }
}

}  // namespace vknerf

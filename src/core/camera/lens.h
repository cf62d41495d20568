#pragma once
// The lens models of vknerf/camera.h on the host, in float or double: checkLens() (lens_check.cpp)
// and pixelDirection() use them, the tests take them as the reference, and shaders/rays/camera.glsl
// mirrors them step for step. Points are normalised OpenCV image coordinates (x right, y down):
// distort() maps an undistorted point to the distorted one the photo records, undistort() inverts it
// by Newton's method from the distorted point itself (as instant-ngp does), with a fixed step count
// and no early exit, so that the shader runs the same steps in every invocation.
#include <array>
#include <cmath>

#include "vknerf/camera.h"

namespace vknerf::core {

// Newton steps of undistort(), here and in camera.glsl (kLensNewtonSteps). checkLens() proves at load
// that this many steps converge over the whole image, so the count is part of the lens contract.
inline constexpr int kLensNewtonSteps = 20;
// A Jacobian (or derivative) at most this large in magnitude stops the iteration where it is.
inline constexpr double kLensSingular = 1e-12;
// A direction component beyond this is no ray (rotated into the world it could overflow a float).
inline constexpr double kLensLargest = 1e18;

template <class T> struct Point2 {
  T x, y;
};

// OpenCV's rational radial factor at r2 = x^2 + y^2, and its derivative with respect to r2.
template <class T> void opencvRadial(const Lens& l, T r2, T& radial, T& dRadial) {
  const T a = T(1) + r2 * (T(l.k1) + r2 * (T(l.k2) + r2 * T(l.k3)));
  const T b = T(1) + r2 * (T(l.k4) + r2 * (T(l.k5) + r2 * T(l.k6)));
  const T da = T(l.k1) + r2 * (T(2) * T(l.k2) + r2 * T(3) * T(l.k3));
  const T db = T(l.k4) + r2 * (T(2) * T(l.k5) + r2 * T(3) * T(l.k6));
  radial = a / b;
  dRadial = (da * b - a * db) / (b * b);
}

// The denominator of OpenCV's rational radial factor: the model has a pole where it reaches 0.
template <class T> T opencvRadialDenominator(const Lens& l, T r2) {
  return T(1) + r2 * (T(l.k4) + r2 * (T(l.k5) + r2 * T(l.k6)));
}

// The fisheye model's distorted angle theta_d(theta) and its derivative.
template <class T> void fisheyeAngle(const Lens& l, T theta, T& thetaD, T& dThetaD) {
  const T t2 = theta * theta;
  thetaD = theta * (T(1) + t2 * (T(l.k1) + t2 * (T(l.k2) + t2 * (T(l.k3) + t2 * T(l.k4)))));
  dThetaD = T(1) + t2 * (T(3) * T(l.k1) + t2 * (T(5) * T(l.k2) + t2 * (T(7) * T(l.k3) + t2 * T(9) * T(l.k4))));
}

template <class T> Point2<T> distort(const Lens& l, T x, T y) {
  switch (l.model) {
    case LensModel::OpenCV: {
      const T r2 = x * x + y * y;
      T radial, dRadial;
      opencvRadial(l, r2, radial, dRadial);
      return {x * radial + T(2) * T(l.p1) * x * y + T(l.p2) * (r2 + T(2) * x * x),
              y * radial + T(l.p1) * (r2 + T(2) * y * y) + T(2) * T(l.p2) * x * y};
    }
    case LensModel::Fisheye: {
      const T r = std::sqrt(x * x + y * y);
      if (!(r > T(0))) return {x, y};
      T thetaD, dThetaD;
      fisheyeAngle(l, T(std::atan(r)), thetaD, dThetaD);
      return {x * thetaD / r, y * thetaD / r};
    }
    case LensModel::Pinhole: break;
  }
  return {x, y};
}

// Jacobian of the OpenCV model's distort() at (x, y), row-major: d(x_d, y_d) / d(x, y).
template <class T> std::array<T, 4> opencvJacobian(const Lens& l, T x, T y) {
  const T r2 = x * x + y * y;
  T radial, dRadial;
  opencvRadial(l, r2, radial, dRadial);
  const T p1 = T(l.p1), p2 = T(l.p2);
  return {radial + T(2) * x * x * dRadial + T(2) * p1 * y + T(6) * p2 * x,
          T(2) * x * y * dRadial + T(2) * p1 * x + T(2) * p2 * y,
          T(2) * x * y * dRadial + T(2) * p1 * x + T(2) * p2 * y,
          radial + T(2) * y * y * dRadial + T(6) * p1 * y + T(2) * p2 * x};
}

// Newton on the 2x2 system distort(p) = (xd, yd), from p = (xd, yd).
template <class T> Point2<T> undistortOpenCV(const Lens& l, T xd, T yd) {
  T x = xd, y = yd;
  for (int i = 0; i < kLensNewtonSteps; ++i) {
    const Point2<T> d = distort(l, x, y);
    const T ex = d.x - xd, ey = d.y - yd;
    const auto J = opencvJacobian(l, x, y);
    const T det = J[0] * J[3] - J[1] * J[2];
    if (!(std::fabs(det) > T(kLensSingular))) continue;  // the shader takes a zero step
    x -= (ex * J[3] - ey * J[1]) / det;
    y -= (ey * J[0] - ex * J[2]) / det;
  }
  return {x, y};
}

// Newton on theta_d(theta) = rd, from theta = rd; clamped to [0, pi/2], the angles the model describes.
template <class T> T fisheyeTheta(const Lens& l, T rd) {
  T theta = rd;
  for (int i = 0; i < kLensNewtonSteps; ++i) {
    T thetaD, dThetaD;
    fisheyeAngle(l, theta, thetaD, dThetaD);
    if (!(std::fabs(dThetaD) > T(kLensSingular))) continue;
    theta -= (thetaD - rd) / dThetaD;
  }
  return std::fmin(std::fmax(theta, T(0)), T(1.5707963267948966));
}

template <class T> Point2<T> undistort(const Lens& l, T xd, T yd) {
  switch (l.model) {
    case LensModel::OpenCV: return undistortOpenCV(l, xd, yd);
    case LensModel::Fisheye: {
      const T rd = std::sqrt(xd * xd + yd * yd);
      if (!(rd > T(0))) return {xd, yd};
      const T s = T(std::tan(fisheyeTheta(l, rd))) / rd;
      return {xd * s, yd * s};
    }
    case LensModel::Pinhole: break;
  }
  return {xd, yd};
}

// Direction (not normalised) of the ray through the distorted normalised point (xd, yd), in the
// OpenCV camera frame (x right, y down, z forward): (x, y, 1) of the undistorted point, or for the
// fisheye (sin theta u, cos theta) with u the unit image direction, which stays finite up to 90
// degrees. A non-finite or absurdly large result (only a lens checkLens() rejects gives one) falls
// back to the pinhole ray, so no ray is ever NaN.
template <class T> std::array<T, 3> lensDirection(const Lens& l, T xd, T yd) {
  std::array<T, 3> d{xd, yd, T(1)};
  if (l.model == LensModel::OpenCV) {
    const Point2<T> p = undistortOpenCV(l, xd, yd);
    d = {p.x, p.y, T(1)};
  } else if (l.model == LensModel::Fisheye) {
    const T rd = std::sqrt(xd * xd + yd * yd);
    const T theta = fisheyeTheta(l, rd), s = rd > T(0) ? T(std::sin(theta)) / rd : T(1);
    d = {xd * s, yd * s, T(std::cos(theta))};
  }
  for (T v : d)
    if (!(std::fabs(v) < T(kLensLargest))) return {xd, yd, T(1)};
  return d;
}

}  // namespace vknerf::core

// The camera builders of include/vknerf/camera.h: the one place the look-at frame is computed (the
// command line's orbit, the viewer, the self-check and the tests all build their cameras here); and
// a pixel's ray direction through the lens.
#include "vknerf/camera.h"

#include <cmath>

#include "core/camera/lens.h"

namespace vknerf {
namespace {

using Vec3 = std::array<float, 3>;

constexpr float kPi = 3.14159265f;

float radians(float degrees) { return degrees * kPi / 180.0f; }

Vec3 normalized(const Vec3& v) {
  const float n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

}  // namespace

std::array<float, 16> lookAt(const Vec3& eye, const Vec3& target, const Vec3& up) {
  // The camera looks down its -Z, so its +Z ("back") points from the target to the eye.
  const Vec3 back = normalized({eye[0] - target[0], eye[1] - target[1], eye[2] - target[2]});
  const Vec3 right = normalized(cross(up, back));
  const Vec3 camUp = cross(back, right);  // unit: back and right are orthonormal
  return {right[0], camUp[0], back[0], eye[0],  //
          right[1], camUp[1], back[1], eye[1],  //
          right[2], camUp[2], back[2], eye[2],  //
          0,        0,        0,       1};
}

std::array<float, 16> orbitPose(const Vec3& centre, float radius, float elevationDegrees, uint32_t index,
                                uint32_t count) {
  // The frame in closed form from the two angles rather than through lookAt: this is how the
  // command line's orbit renders have always been posed, and the same floats keep them bit-identical.
  const float el = radians(elevationDegrees);
  const float az = 2.0f * kPi * float(index) / float(count);
  const Vec3 back{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  const Vec3 right{-std::sin(az), std::cos(az), 0};
  const Vec3 up = cross(back, right);
  return {right[0], up[0], back[0], centre[0] + radius * back[0],  //
          right[1], up[1], back[1], centre[1] + radius * back[1],  //
          right[2], up[2], back[2], centre[2] + radius * back[2],  //
          0,        0,     0,       1};
}

Camera pinholeFromFocal(uint32_t width, uint32_t height, float focalPixels, const std::array<float, 16>& c2w) {
  Camera c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = focalPixels;
  c.cx = 0.5f * float(width);
  c.cy = 0.5f * float(height);
  c.c2w = c2w;
  return c;
}

Camera pinholeFromFov(uint32_t width, uint32_t height, float fovXDegrees, const std::array<float, 16>& c2w) {
  return pinholeFromFocal(width, height, 0.5f * float(width) / std::tan(0.5f * radians(fovXDegrees)), c2w);
}

std::array<float, 3> pixelDirection(const Camera& c, float x, float y) {
  const auto d = core::lensDirection(c.lens, (double(x) - c.cx) / c.fx, (double(y) - c.cy) / c.fy);
  const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return {float(d[0] / n), float(-d[1] / n), float(-d[2] / n)};  // OpenCV (y down, z forward) -> OpenGL
}

}  // namespace vknerf

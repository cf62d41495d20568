#pragma once
// A posed camera in the nerf_synthetic / OpenGL convention: camera-to-world matrix, camera looking
// down -Z with +Y up and +X right; pixel (x, y) counts rows downwards; optional lens distortion.
#include <array>
#include <cstdint>
#include <string>

namespace vknerf {

inline constexpr std::array<float, 16> kIdentityPose{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

// Lens distortion, in OpenCV's conventions on normalised image coordinates (x, y) = (X/Z, Y/Z) in
// the OpenCV camera frame (x right, y down); pixel = (fx * x_d + cx, fy * y_d + cy).
//   Pinhole:  no distortion.
//   OpenCV:   radial-tangential with the rational radial term, r2 = x^2 + y^2,
//             radial = (1 + k1 r2 + k2 r2^2 + k3 r2^3) / (1 + k4 r2 + k5 r2^2 + k6 r2^3),
//             x_d = x radial + 2 p1 x y + p2 (r2 + 2 x^2), y_d = y radial + p1 (r2 + 2 y^2) + 2 p2 x y.
//             COLMAP's SIMPLE_RADIAL, RADIAL, OPENCV and FULL_OPENCV are special cases.
//   Fisheye:  OpenCV's fisheye (equidistant) model, theta = atan(r), r = sqrt(r2),
//             theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
//             (x_d, y_d) = (theta_d / r) (x, y). COLMAP's OPENCV_FISHEYE.
enum class LensModel : uint32_t { Pinhole = 0, OpenCV = 1, Fisheye = 2 };

struct Lens {
  LensModel model = LensModel::Pinhole;
  float k1 = 0, k2 = 0, k3 = 0, k4 = 0, k5 = 0, k6 = 0;  // Fisheye uses k1..k4 only
  float p1 = 0, p2 = 0;                                  // OpenCV only
};

struct Camera {
  float fx = 0, fy = 0, cx = 0, cy = 0;  // focal lengths and principal point, pixels
  uint32_t width = 0, height = 0;
  std::array<float, 16> c2w = kIdentityPose;  // row-major 4x4
  Lens lens;                                  // applied where rays are generated
};

// Throws vknerf::Error unless the lens can be inverted over the camera's whole image, the corners
// included: its coefficients are finite; its radial map (r -> r radial(r^2), or theta -> theta_d for
// the fisheye) rises monotonically out to the farthest image corner, with no pole and, for the
// fisheye, within 90 degrees of the axis; and on a 17 x 17 grid of pixel positions from edge to edge
// the ray generator's fixed Newton iteration converges, distort(undistort(p)) returning p to within
// 0.01 pixel, onto the fold-free branch. The message reads
//   "<where>: k1 = -10: lens distortion does not invert over the image (fails at pixel (0, 0): <why>)".
// A pinhole camera always passes. Dataset loading and the ray generator call it; a camera built by
// hand can be checked the same way.
void checkLens(const Camera& camera, const std::string& where);

// A training image's camera with the image's name, as a checkpoint records it (Model::trainingCameras,
// vknerf export cameras). `name` is the image's path as Dataset::names held it (relative paths to the
// folder training ran in); empty when the training set named no image.
struct TrainedCamera {
  std::string name;
  Camera camera;
};

struct Aabb {
  std::array<float, 3> min{-1, -1, -1};
  std::array<float, 3> max{1, 1, 1};
};

// ---- Building cameras (src/core/camera/camera.cpp) ----

// Camera-to-world (row-major, the convention above) of a camera at `eye` looking at `target`: its
// -Z axis points from eye to target and its +Y is the part of `up` perpendicular to that. `up` is
// the world's up direction, of any length; it must not be parallel to target - eye.
std::array<float, 16> lookAt(const std::array<float, 3>& eye, const std::array<float, 3>& target,
                             const std::array<float, 3>& up);

// Camera `index` of `count` spaced evenly on a circle around `centre` in a +Z-up world
// (nerf_synthetic's), looking at the centre with the image's right horizontal: `radius` from it,
// `elevationDegrees` above its XY plane (strictly between -90 and 90), at azimuth
// 360 * index / count degrees from +X towards +Y.
std::array<float, 16> orbitPose(const std::array<float, 3>& centre, float radius, float elevationDegrees,
                                uint32_t index, uint32_t count);

// A pinhole camera of width x height pixels with square pixels and its principal point at the image
// centre, its focal length given by the horizontal field of view or in pixels.
// ---- Rays ----
// Unit direction, in the camera's own frame (the OpenGL convention above: x right, y up, looking down
// -z), of the ray through pixel position (x, y) (pixel edges at integers, rows downwards), through
// the lens: the inverse the ray generator applies.
std::array<float, 3> pixelDirection(const Camera& camera, float x, float y);

Camera pinholeFromFov(uint32_t width, uint32_t height, float fovXDegrees,
                      const std::array<float, 16>& c2w = kIdentityPose);
Camera pinholeFromFocal(uint32_t width, uint32_t height, float focalPixels,
                        const std::array<float, 16>& c2w = kIdentityPose);

}  // namespace vknerf

// COLMAP camera models: https://colmap.github.io/cameras.html lists the parameter order of each.
#include "io/colmap/colmap_camera.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "vknerf/error.h"

namespace vknerf::io::detail {
namespace {

const ColmapCameraModel kModels[] = {
    {0, "SIMPLE_PINHOLE", 3}, {1, "PINHOLE", 4},           {2, "SIMPLE_RADIAL", 4},
    {3, "RADIAL", 5},         {4, "OPENCV", 8},            {5, "OPENCV_FISHEYE", 8},
    {6, "FULL_OPENCV", 12},   {7, "FOV", 5},               {8, "SIMPLE_RADIAL_FISHEYE", 4},
    {9, "RADIAL_FISHEYE", 5}, {10, "THIN_PRISM_FISHEYE", 12}};

}  // namespace

const ColmapCameraModel* colmapModelByName(std::string_view name) {
  for (const auto& m : kModels)
    if (name == m.name) return &m;
  return nullptr;
}

const ColmapCameraModel* colmapModelById(int64_t id) {
  for (const auto& m : kModels)
    if (id == m.id) return &m;
  return nullptr;
}

Intrinsics colmapIntrinsics(const ColmapCameraModel& model, uint64_t cameraId, uint64_t width, uint64_t height,
                            std::span<const double> p, const std::string& where) {
  auto fail = [&](const std::string& what) { throw Error(where + ": " + what); };
  // Where the focal lengths and the distortion parameters sit, and which Lens field each
  // distortion parameter fills (COLMAP's order, sensor/models.h).
  bool singleFocal = false;
  LensModel lensModel = LensModel::Pinhole;
  std::vector<float Lens::*> fields;
  switch (model.id) {
    case 0: singleFocal = true; break;                                                // SIMPLE_PINHOLE f cx cy
    case 1: break;                                                                    // PINHOLE fx fy cx cy
    case 2: singleFocal = true, lensModel = LensModel::OpenCV, fields = {&Lens::k1}; break;  // SIMPLE_RADIAL k
    case 3: singleFocal = true, lensModel = LensModel::OpenCV, fields = {&Lens::k1, &Lens::k2}; break;  // RADIAL
    case 4: lensModel = LensModel::OpenCV, fields = {&Lens::k1, &Lens::k2, &Lens::p1, &Lens::p2}; break;  // OPENCV
    case 5: lensModel = LensModel::Fisheye, fields = {&Lens::k1, &Lens::k2, &Lens::k3, &Lens::k4}; break;  // OPENCV_FISHEYE
    case 6:  // FULL_OPENCV k1 k2 p1 p2 k3 k4 k5 k6, k4..k6 the rational denominator as in OpenCV
      lensModel = LensModel::OpenCV;
      fields = {&Lens::k1, &Lens::k2, &Lens::p1, &Lens::p2, &Lens::k3, &Lens::k4, &Lens::k5, &Lens::k6};
      break;
    // SIMPLE_RADIAL_FISHEYE and RADIAL_FISHEYE: theta_d = theta (1 + k1 theta^2 [+ k2 theta^4]), the
    // OpenCV fisheye with the higher terms zero.
    case 8: singleFocal = true, lensModel = LensModel::Fisheye, fields = {&Lens::k1}; break;
    case 9: singleFocal = true, lensModel = LensModel::Fisheye, fields = {&Lens::k1, &Lens::k2}; break;
    default:  // FOV, THIN_PRISM_FISHEYE
      fail(std::string("camera model ") + model.name + " of camera " + std::to_string(cameraId) +
           " is not handled (pinhole, SIMPLE_RADIAL, RADIAL, OPENCV, FULL_OPENCV and the OpenCV fisheye models are)");
  }
  const size_t firstDistortion = singleFocal ? 3 : 4;
  if (p.size() != model.params)
    fail(std::string(model.name) + " needs " + std::to_string(model.params) + " parameters, got " + std::to_string(p.size()));
  if (width == 0 || height == 0 || width > 1000000 || height > 1000000)
    fail("image size " + std::to_string(width) + "x" + std::to_string(height) + " is not valid");
  for (double v : p)
    if (!std::isfinite(float(v))) fail("camera parameter " + std::to_string(v) + " is not finite as a float");
  Intrinsics in;
  in.focalFieldX = in.focalFieldY = "camera " + std::to_string(cameraId) + "'s parameters";
  in.width = uint32_t(width);
  in.height = uint32_t(height);
  in.fx = p[0];
  in.fy = singleFocal ? p[0] : p[1];
  in.cx = p[singleFocal ? 1 : 2];
  in.cy = p[singleFocal ? 2 : 3];
  if (!(in.fx > 0) || !(in.fy > 0)) fail("focal length must be positive");
  for (size_t i = 0; i < fields.size(); ++i) in.lens.*fields[i] = float(p[firstDistortion + i]);
  const bool distorted = std::any_of(fields.begin(), fields.end(), [&](auto f) { return in.lens.*f != 0; });
  if (distorted) {
    in.lens.model = lensModel;
    Camera c;
    c.fx = float(in.fx), c.fy = float(in.fy), c.cx = float(in.cx), c.cy = float(in.cy);
    c.width = in.width, c.height = in.height;
    c.lens = in.lens;
    checkLens(c, where + ": " + model.name + " camera " + std::to_string(cameraId));
  }
  return in;
}

}  // namespace vknerf::io::detail

// COLMAP camera models: https://colmap.github.io/cameras.html lists the parameter order of each.
#include "io/colmap_camera.h"

#include <cmath>

#include "vknerf/error.h"

namespace vknerf::nerf::detail {
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
  // Index where the distortion parameters start; models with one focal length put f, cx, cy first.
  size_t firstDistortion = 0;
  bool singleFocal = false;
  switch (model.id) {
    case 0: firstDistortion = 3, singleFocal = true; break;
    case 1: firstDistortion = 4; break;
    case 2: case 3: firstDistortion = 3, singleFocal = true; break;
    case 4: case 6: firstDistortion = 4; break;
    default: fail(std::string("camera model ") + model.name + " is not handled (pinhole models only: undistort the images first)");
  }
  if (p.size() != model.params)
    fail(std::string(model.name) + " needs " + std::to_string(model.params) + " parameters, got " + std::to_string(p.size()));
  if (width == 0 || height == 0 || width > 1000000 || height > 1000000)
    fail("image size " + std::to_string(width) + "x" + std::to_string(height) + " is not valid");
  for (double v : p)
    if (!std::isfinite(float(v))) fail("camera parameter " + std::to_string(v) + " is not finite as a float");
  for (size_t i = firstDistortion; i < p.size(); ++i)
    if (p[i] != 0) fail(std::string(model.name) + " camera " + std::to_string(cameraId) + " has nonzero distortion: lens distortion is not handled (undistort the images first)");
  Intrinsics in;
  in.width = uint32_t(width);
  in.height = uint32_t(height);
  in.fx = p[0];
  in.fy = singleFocal ? p[0] : p[1];
  in.cx = p[singleFocal ? 1 : 2];
  in.cy = p[singleFocal ? 2 : 3];
  if (!(in.fx > 0) || !(in.fy > 0)) fail("focal length must be positive");
  return in;
}

}  // namespace vknerf::nerf::detail

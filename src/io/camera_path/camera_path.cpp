// Camera paths (vknerf/camera_path.h): the format told apart by content, and nerfstudio's reader
// (instant-ngp's is io/camera_path/ngp_camera_path.cpp). nerfstudio's poses are camera-to-world in the OpenGL
// convention, as vknerf's, and its fov is vertical, in degrees (ns-render turns it into the focal
// length (H / 2) / tan(fov / 2)).
#include "vknerf/camera_path.h"

#include <cmath>
#include <numbers>

#include "io/dataset/dataset_loaders.h"
#include "io/file/json_file.h"
#include "io/camera_path/ngp_camera_path.h"
#include "vknerf/error.h"

namespace vknerf {

using nlohmann::json;
using io::detail::fieldError;
using io::detail::JsonFile;

namespace {

constexpr double kMaxSize = 16384;

double number(const JsonFile& f, const json& obj, const char* key, const std::string& prefix, double lo, double hi,
              bool loOpen) {
  auto v = io::detail::optNumber(f, obj, key, prefix);
  if (!v) fieldError(f, prefix + key, "is missing");
  if (!((loOpen ? *v > lo : *v >= lo) && *v <= hi))
    fieldError(f, prefix + key, "must be in " + std::string(loOpen ? "(" : "[") + std::to_string(lo) + ", " +
                                    std::to_string(hi) + "], got " + std::to_string(*v));
  return *v;
}

uint32_t pixels(const JsonFile& f, const char* key) {
  double v = number(f, f.root, key, "", 1, kMaxSize, false);
  if (v != std::floor(v)) fieldError(f, key, "must be a whole number of pixels, got " + std::to_string(v));
  return uint32_t(v);
}

CameraPath readNerfstudioCameraPath(const JsonFile& f) {
  if (auto t = f.root.find("camera_type"); t != f.root.end() && !t->is_null()) {
    if (!t->is_string() || t->get<std::string>() != "perspective")
      fieldError(f, "camera_type", "must be \"perspective\" (fisheye and equirectangular paths are not rendered)");
  }
  const uint32_t width = pixels(f, "render_width"), height = pixels(f, "render_height");
  CameraPath out;
  if (f.root.contains("fps")) out.fps = number(f, f.root, "fps", "", 0, 1000, true);
  auto list = f.root.find("camera_path");
  if (list == f.root.end()) fieldError(f, "camera_path", "is missing");
  if (!list->is_array()) fieldError(f, "camera_path", "must be an array");
  if (list->empty()) fieldError(f, "camera_path", "is empty");
  for (size_t i = 0; i < list->size(); ++i) {
    const std::string prefix = "camera_path[" + std::to_string(i) + "].";
    const json& entry = (*list)[i];
    if (!entry.is_object()) fieldError(f, "camera_path[" + std::to_string(i) + "]", "must be an object");
    io::detail::FrameSpec spec;
    spec.where = f.name() + ": camera_path[" + std::to_string(i) + "]";
    spec.c2w = io::detail::readMatrixField(f, entry, "camera_to_world", prefix);
    io::detail::checkRigid(spec.c2w, f.name() + ": " + prefix + "camera_to_world", "the pose");
    const double fov = number(f, entry, "fov", prefix, 0, 180, true);
    if (fov >= 180) fieldError(f, prefix + "fov", "must be below 180 degrees");
    spec.intrinsics.angleY = fov * std::numbers::pi / 180;
    spec.intrinsics.focalFieldX = spec.intrinsics.focalFieldY = "fov";
    spec.poseField = "camera_to_world";
    spec.intrinsics.width = width;
    spec.intrinsics.height = height;
    out.cameras.push_back(io::detail::completeCamera(spec, width, height));
  }
  return out;
}

}  // namespace

CameraPath loadCameraPath(const std::string& path, const CameraPathOptions& options) {
  const JsonFile f = io::detail::readJson(path, "camera path");
  if (!f.root.contains("camera_path") && f.root.contains("path")) return io::detail::readNgpCameraPath(f, options);
  if (!f.root.contains("camera_path"))
    fieldError(f, "camera_path", "is missing (nor is there instant-ngp's keyframe list 'path')");
  return readNerfstudioCameraPath(f);
}

}  // namespace vknerf

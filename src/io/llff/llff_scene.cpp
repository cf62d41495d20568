// LLFF's poses_bounds.npy (Mildenhall et al., Local Light Field Fusion, 2019; the real scenes of
// NeRF and of most papers since) as a SceneSpec.
//
// Row i of the N x 17 array is a 3x5 matrix row by row, [R | t | hwf], then the near and far bounds.
// R's columns are the camera's down, right and back axes in the world (LLFF's imgs2poses reorders
// COLMAP's [right, down, forward] so), t is its position, hwf the height, width and focal length in
// pixels of the photos in images/ (images_N/ holds them N times smaller). vknerf's camera-to-world
// (OpenGL: right, up, back) is therefore [R1, -R0, R2 | t], as NeRF's load_llff builds it. The
// world frame is kept: load_llff's recentring and its rescale by the nearest bound are choices of
// its training, not part of the data, and a scene written both as transforms.json and as
// poses_bounds.npy must give the same rays. The bounds
// are LLFF's near and far percentiles of the depths, along the optical axis, of the COLMAP points
// each camera sees.
#include <cstdio>

#include "io/dataset/dataset_loaders.h"
#include "io/llff/llff_photos.h"
#include "io/llff/npy.h"
#include "vknerf/error.h"

namespace vknerf::io::detail {
namespace {

constexpr size_t kColumns = 17;
constexpr uint32_t kHoldEvery = 8;  // llffhold: every 8th photo, from the first, is held out
constexpr double kMaxSize = 1e6;    // pixels a side, as transforms.json's w and h

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// Names the value in column c of a row: "R[1][2]", "t[0]", "height", "near", ...
std::string columnName(size_t c) {
  if (c == 15) return "near";
  if (c == 16) return "far";
  const size_t r = c / 5, k = c % 5;
  if (k < 3) return "R[" + std::to_string(r) + "][" + std::to_string(k) + "]";
  if (k == 3) return "t[" + std::to_string(r) + "]";
  return r == 0 ? "height" : r == 1 ? "width" : "focal";
}

struct Row {
  std::array<double, 16> c2w{};
  double height = 0, width = 0, focal = 0, nearBound = 0, farBound = 0;
};

// Checks row i's values and turns its pose into vknerf's convention.
Row readRow(const double* v, const std::string& where) {
  for (size_t c = 0; c < kColumns; ++c) {
    if (!std::isfinite(v[c])) throw Error(where + ", column " + std::to_string(c) + " (" + columnName(c) + ") is not finite");
    if (!(std::fabs(v[c]) <= kDeviceLimit))
      throw Error(where + ", column " + std::to_string(c) + " (" + columnName(c) + ") value " + number(v[c]) +
                  " is beyond the range the device computes with (|x| <= 1e15)");
  }
  Row r;
  r.height = v[4];
  r.width = v[9];
  r.focal = v[14];
  r.nearBound = v[15];
  r.farBound = v[16];
  for (const auto& [value, name] : {std::pair{r.height, "height"}, {r.width, "width"}})
    if (!(value >= 1 && value <= kMaxSize && value == std::floor(value)))
      throw Error(where + ": hwf " + name + " " + number(value) + " must be a whole number of pixels in [1, 1e6]");
  if (!(r.focal > 0)) throw Error(where + ": hwf focal " + number(r.focal) + " must be positive");
  if (!(r.nearBound > 0)) throw Error(where + ": near bound " + number(r.nearBound) + " must be positive");
  if (!(r.nearBound < r.farBound))
    throw Error(where + ": near bound " + number(r.nearBound) + " is not below the far bound " + number(r.farBound));
  // Row k of the 3x5 matrix is v[5k .. 5k + 4]; columns [down, right, back] become [right, up, back].
  for (int k = 0; k < 3; ++k) {
    r.c2w[4 * k + 0] = v[5 * k + 1];
    r.c2w[4 * k + 1] = -v[5 * k + 0];
    r.c2w[4 * k + 2] = v[5 * k + 2];
    r.c2w[4 * k + 3] = v[5 * k + 3];
  }
  r.c2w[15] = 1;
  checkRigid(r.c2w, where, "pose");
  return r;
}

}  // namespace

SceneSpec readLlff(const fs::path& file, const DatasetOptions& options) {
  const NpyArray a = readNpy(file);
  const std::string name = file.string();
  if (a.shape.size() != 2 || a.shape[1] != kColumns) {
    std::string shape;
    for (uint64_t d : a.shape) shape += (shape.empty() ? "" : ", ") + std::to_string(d);
    throw Error(name + ": shape (" + shape + (a.shape.size() == 1 ? ",)" : ")") +
                " is not (N, 17): a row per photo of its 3x5 pose [R | t | hwf], near and far");
  }
  const size_t n = a.shape[0];
  if (n == 0) throw Error(name + ": shape (0, 17) holds no photos");

  std::vector<Row> rows;
  for (size_t i = 0; i < n; ++i) rows.push_back(readRow(&a.values[i * kColumns], name + ": row " + std::to_string(i)));

  // Every row's frustum at the size hwf states (a resized copy of a photo sees the same frustum).
  SceneSpec scene;
  std::vector<FrameSpec> full(n);
  std::vector<Camera> cameras;
  std::vector<std::array<float, 2>> bounds;
  for (size_t i = 0; i < n; ++i) {
    FrameSpec& f = full[i];
    f.where = name + ": row " + std::to_string(i);
    f.intrinsics.fx = f.intrinsics.fy = rows[i].focal;
    f.intrinsics.width = uint32_t(rows[i].width);
    f.intrinsics.height = uint32_t(rows[i].height);
    f.c2w = rows[i].c2w;
    f.depthBounds = std::array<float, 2>{float(rows[i].nearBound), float(rows[i].farBound)};
    cameras.push_back(completeCamera(f, f.intrinsics.width, f.intrinsics.height));
    bounds.push_back(*f.depthBounds);
  }
  scene.hasBox = true;
  const Aabb frustums = boxFromFrustums(cameras, bounds);
  for (int k = 0; k < 3; ++k)
    if (!(std::fabs(frustums.min[k]) <= kDeviceLimit && std::fabs(frustums.max[k]) <= kDeviceLimit))
      throw Error(name + ": the frustums between the near and far bounds reach beyond 1e15, the range the device computes with");
  scene.box = cascadedBoxFromDepths(cameras, bounds, frustums, scene.aabbScale);
  scene.boxSource = "llff bounds";

  const LlffPhotos photos = findLlffPhotos(file, n, options.downscale, full[0].intrinsics.width, full[0].intrinsics.height);
  if (photos.factor > 1) {
    // Copies smaller than hwf states: their intrinsics are hwf's scaled by their actual size over
    // hwf's (completeCamera, which checks that size against the factor), the rest of the downscale
    // applied on top as for any photo.
    scene.downscale = photos.downscale;
    for (FrameSpec& f : full) {
      f.intrinsics.statedWidth = f.intrinsics.width;
      f.intrinsics.statedHeight = f.intrinsics.height;
      f.intrinsics.statedFactor = photos.factor;
      f.intrinsics.statedWidthField = "hwf width";
      f.intrinsics.statedHeightField = "hwf height";
      f.intrinsics.width = f.intrinsics.height = 0;
    }
  }
  for (size_t i = 0; i < n; ++i) {
    full[i].image = photos.files[i];
    const bool held = i % kHoldEvery == 0;
    const bool picked = options.split == "all" || held == (options.split != "train");
    (picked ? scene.frames : scene.others).push_back(std::move(full[i]));
  }
  return scene;
}

}  // namespace vknerf::io::detail

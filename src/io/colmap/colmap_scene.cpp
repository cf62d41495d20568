// A COLMAP model (text or binary) as a SceneSpec.
//
// COLMAP stores world-to-camera (R, t) with the quaternion (qw, qx, qy, qz), in the OpenCV camera
// convention (x right, y down, z forward). The camera-to-world pose is [R^T | -R^T t]; negating its
// y and z columns turns it into the OpenGL convention (y up, looking down -z) that vknerf uses.
// COLMAP puts the image origin at the top-left corner of the top-left pixel, so pixel centres sit at
// +0.5 exactly as in vknerf's rays and the principal point carries over unchanged.
#include <algorithm>

#include "io/colmap/colmap_model.h"
#include "vknerf/error.h"

namespace vknerf::io::detail {

void ColmapModel::addCamera(uint64_t id, ColmapCamera camera) {
  const std::string where = camera.where;
  if (!cameras.emplace(id, std::move(camera)).second)
    throw Error(where + ": camera " + std::to_string(id) + " is defined twice");
}

namespace {

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// Rotation matrix of the unit quaternion (w, x, y, z).
std::array<double, 9> rotation(double w, double x, double y, double z) {
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

// Camera-to-world in the OpenGL convention, COLMAP's world frame.
std::array<double, 16> cameraToWorld(const ColmapImage& img) {
  const auto& q = img.q;
  double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  // Text rounding leaves |q| within ~1e-6 of 1; anything far off is corruption, not rounding.
  if (!(std::fabs(norm - 1) <= 1e-2))
    throw Error(img.where + ": quaternion is not unit length (|q| = " + std::to_string(norm) + ")");
  auto R = rotation(q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm);
  std::array<double, 16> m{};
  for (int r = 0; r < 3; ++r) {
    // Row r of R^T is column r of R; negate the camera's y and z axes (columns 1 and 2).
    m[4 * r + 0] = R[0 * 3 + r];
    m[4 * r + 1] = -R[1 * 3 + r];
    m[4 * r + 2] = -R[2 * 3 + r];
    m[4 * r + 3] = -(R[0 * 3 + r] * img.t[0] + R[1 * 3 + r] * img.t[1] + R[2 * 3 + r] * img.t[2]);
  }
  m[15] = 1;
  return m;
}

// Per-axis 1st and 99th percentiles of the points, padded by 5% of the largest extent; false when
// there are fewer than 2 points or they span no volume (or one too large for doubles).
bool pointsBox(const std::vector<std::array<double, 3>>& points, std::array<double, 3>& lo, std::array<double, 3>& hi) {
  const size_t n = points.size();
  if (n < 2) return false;
  double extent = 0;
  std::vector<double> v(n);
  for (int k = 0; k < 3; ++k) {
    for (size_t i = 0; i < n; ++i) v[i] = points[i][k];
    std::sort(v.begin(), v.end());
    lo[k] = v[size_t(0.01 * double(n - 1) + 0.5)];
    hi[k] = v[size_t(0.99 * double(n - 1) + 0.5)];
    extent = std::max(extent, hi[k] - lo[k]);
  }
  if (!(extent > 0) || !std::isfinite(extent)) return false;
  for (int k = 0; k < 3; ++k) {
    lo[k] -= 0.05 * extent;
    hi[k] += 0.05 * extent;
  }
  return true;
}

// The fields of an image's pose in images.txt (images.bin holds the same).
constexpr const char* kColmapPose = "pose (QW QX QY QZ TX TY TZ)";

// The outer box's side over the points box's, a power of two (instant-ngp's aabb_scale): enough to
// hold 99.9% of the points (by their largest coordinate offset from the box centre, in units of the
// box's largest half extent), at most kMaxOuterScale. The points box leaves out what the cameras see
// sparsely: the walls of a room, a far background. Inside the points box the cascades keep the
// detail; the outer ones hold the rest, so that a ray through an opaque photo finds its surface
// inside the box instead of borrowing it from a background.
constexpr double kOuterShare = 0.999;
constexpr float kMaxOuterScale = 16;

float outerScale(const std::vector<std::array<double, 3>>& points, const std::array<double, 3>& centre, double half) {
  std::vector<double> d;
  d.reserve(points.size());
  for (const auto& p : points) {
    double m = 0;
    for (int k = 0; k < 3; ++k) m = std::max(m, std::fabs(p[k] - centre[k]) / half);
    if (std::isfinite(m)) d.push_back(m);
  }
  if (d.empty()) return 1;
  const size_t q = std::min(d.size() - 1, size_t(kOuterShare * double(d.size() - 1) + 0.5));
  std::nth_element(d.begin(), d.begin() + q, d.end());
  float scale = 1;
  while (scale < kMaxOuterScale && scale < d[q]) scale *= 2;
  return scale;
}

struct PosedImage {
  const ColmapImage* image;
  const Intrinsics* intrinsics;
  std::array<double, 16> c2w;
};

SceneSpec toScene(const ColmapModel& model, const fs::path& imagesDir, const DatasetOptions& options) {
  if (model.cameras.empty()) throw Error("'" + model.camerasFile.string() + "' defines no cameras");
  std::map<uint64_t, Intrinsics> intrinsics;
  for (const auto& [id, c] : model.cameras)
    intrinsics.emplace(id, colmapIntrinsics(*c.model, id, c.width, c.height, c.params, c.where));
  if (model.images.empty()) throw Error("'" + model.imagesFile.string() + "' lists no images");

  std::vector<PosedImage> images;
  for (const ColmapImage& img : model.images) {
    auto cam = intrinsics.find(img.cameraId);
    if (cam == intrinsics.end())
      throw Error(img.where + ": image '" + img.name + "' uses camera " + std::to_string(img.cameraId) + ", which " +
                  model.camerasFile.filename().string() + " does not define");
    images.push_back({&img, &cam->second, cameraToWorld(img)});
  }
  // COLMAP numbers images in the order it registered them; the name order is stable across runs.
  std::stable_sort(images.begin(), images.end(), [](const auto& a, const auto& b) { return a.image->name < b.image->name; });

  std::array<double, 3> lo, hi;
  SceneSpec scene;
  scene.hasBox = true;
  if (pointsBox(model.points, lo, hi)) {
    scene.boxSource = "points3D";
  } else {
    std::vector<Camera> all;
    for (const auto& img : images) {
      FrameSpec f{img.image->where, {}, {}, *img.intrinsics, img.c2w, kColmapPose};
      all.push_back(completeCamera(f, f.intrinsics.width, f.intrinsics.height));
    }
    Aabb b = boxFromCameras(all);
    for (int k = 0; k < 3; ++k) lo[k] = b.min[k], hi[k] = b.max[k];
    scene.boxSource = "cameras";
  }
  // Translate and scale uniformly (a similarity keeps poses rigid) so the box is centred at the
  // origin with its largest half extent 1.
  double centre[3], half = 0;
  for (int k = 0; k < 3; ++k) {
    centre[k] = 0.5 * (lo[k] + hi[k]);
    half = std::max(half, 0.5 * (hi[k] - lo[k]));
  }
  const double s = 1.0 / half;
  if (scene.boxSource == "points3D") scene.aabbScale = outerScale(model.points, {centre[0], centre[1], centre[2]}, half);
  for (int k = 0; k < 3; ++k) {
    scene.box.min[k] = float((lo[k] - centre[k]) * s * scene.aabbScale);
    scene.box.max[k] = float((hi[k] - centre[k]) * s * scene.aabbScale);
  }

  std::vector<size_t> pick = holdoutIndices(images.size(), options.holdoutFraction, options.split);
  std::vector<bool> picked(images.size(), false);
  for (size_t i : pick) picked[i] = true;
  for (size_t i = 0; i < images.size(); ++i) {
    FrameSpec f;
    f.where = images[i].image->where;
    f.intrinsics = *images[i].intrinsics;
    f.c2w = images[i].c2w;
    f.poseField = kColmapPose;
    for (int k = 0; k < 3; ++k) f.c2w[4 * k + 3] = (f.c2w[4 * k + 3] - centre[k]) * s;
    checkRigid(f.c2w, f.where);
    fs::path p = imagesDir / images[i].image->name;
    if (isFile(p))
      f.image = p;
    else
      f.imageTried = p.string();
    (picked[i] ? scene.frames : scene.others).push_back(std::move(f));
  }
  return scene;
}

}  // namespace

ColmapForm colmapForm(const fs::path& modelDir) {
  if (isFile(modelDir / "cameras.txt") || isFile(modelDir / "images.txt")) return ColmapForm::text;
  if (isFile(modelDir / "cameras.bin") || isFile(modelDir / "images.bin")) return ColmapForm::binary;
  return ColmapForm::none;
}

SceneSpec readColmap(const fs::path& modelDir, const fs::path& imagesDir, const DatasetOptions& options) {
  switch (colmapForm(modelDir)) {
    case ColmapForm::text: return toScene(readColmapText(modelDir), imagesDir, options);
    case ColmapForm::binary: return toScene(readColmapBinary(modelDir), imagesDir, options);
    case ColmapForm::none: break;
  }
  throw Error("'" + modelDir.string() + "' holds no COLMAP model (cameras.txt / images.txt or cameras.bin / images.bin)");
}

}  // namespace vknerf::io::detail

// COLMAP text model: cameras.txt, images.txt and (optionally) points3D.txt.
//
// COLMAP stores world-to-camera (R, t) with the quaternion (qw, qx, qy, qz), in the OpenCV camera
// convention (x right, y down, z forward). The camera-to-world pose is [R^T | -R^T t]; negating its
// y and z columns turns it into the OpenGL convention (y up, looking down -z) that vknerf uses.
// COLMAP puts the image origin at the top-left corner of the top-left pixel, so pixel centres sit at
// +0.5 exactly as in vknerf's rays and the principal point carries over unchanged.
#include <algorithm>
#include <charconv>
#include <fstream>
#include <map>
#include <sstream>

#include "io/colmap_camera.h"
#include "io/dataset_loaders.h"
#include "vknerf/error.h"

namespace vknerf::nerf::detail {
namespace {

struct Line {
  size_t number = 0;
  std::string text;
};

std::vector<Line> readLines(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw Error("cannot open '" + path.string() + "'");
  std::vector<Line> lines;
  std::string s;
  for (size_t n = 1; std::getline(in, s); ++n) {
    if (!s.empty() && s.back() == '\r') s.pop_back();
    lines.push_back({n, s});
  }
  return lines;
}

bool skippable(const std::string& s) {
  size_t i = s.find_first_not_of(" \t");
  return i == std::string::npos || s[i] == '#';
}

std::vector<std::string> tokens(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

// The rest of `s` after its first `count` whitespace-separated tokens, trailing blanks removed.
std::string afterTokens(const std::string& s, int count) {
  size_t i = 0;
  for (int k = 0; k < count; ++k) {
    i = s.find_first_not_of(" \t", i);
    i = s.find_first_of(" \t", i);
  }
  i = s.find_first_not_of(" \t", i);
  std::string rest = i == std::string::npos ? "" : s.substr(i);
  while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\t')) rest.pop_back();
  return rest;
}

struct LineError {
  std::string at;  // "path:line"
  [[noreturn]] void operator()(const std::string& what) const { throw Error(at + ": " + what); }
};

LineError at(const fs::path& path, const Line& line) { return {path.string() + ":" + std::to_string(line.number)}; }

double toDouble(const std::string& s, const LineError& fail, const char* what) {
  double v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v))
    fail(std::string(what) + " is not a finite number: '" + s + "'");
  return v;
}

uint64_t toUint(const std::string& s, const LineError& fail, const char* what) {
  uint64_t v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) fail(std::string(what) + " is not a whole number: '" + s + "'");
  return v;
}

struct ColmapCamera {
  Intrinsics intrinsics;
  std::string at;
};

std::map<uint64_t, ColmapCamera> readCameras(const fs::path& path) {
  std::map<uint64_t, ColmapCamera> cams;
  for (const Line& line : readLines(path)) {
    if (skippable(line.text)) continue;
    LineError fail = at(path, line);
    auto t = tokens(line.text);
    if (t.size() < 4) fail("expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
    uint64_t id = toUint(t[0], fail, "CAMERA_ID");
    const ColmapCameraModel* model = colmapModelByName(t[1]);
    if (!model) fail("camera model " + t[1] + " is not a COLMAP camera model");
    uint64_t w = toUint(t[2], fail, "WIDTH"), h = toUint(t[3], fail, "HEIGHT");
    std::vector<double> p;
    for (size_t i = 4; i < t.size(); ++i) p.push_back(toDouble(t[i], fail, "camera parameter"));
    ColmapCamera c;
    c.at = fail.at;
    c.intrinsics = colmapIntrinsics(*model, id, w, h, p, fail.at);
    if (!cams.emplace(id, c).second) fail("camera " + t[0] + " is defined twice");
  }
  if (cams.empty()) throw Error("'" + path.string() + "' defines no cameras");
  return cams;
}

struct ColmapImage {
  std::string name;
  std::array<double, 16> c2w;  // OpenGL convention, COLMAP's world frame
  const ColmapCamera* camera;
  std::string at;
};

// Rotation matrix of the unit quaternion (w, x, y, z).
std::array<double, 9> rotation(double w, double x, double y, double z) {
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

std::vector<ColmapImage> readImages(const fs::path& path, const std::map<uint64_t, ColmapCamera>& cams) {
  std::vector<ColmapImage> images;
  auto lines = readLines(path);
  for (size_t i = 0; i < lines.size(); ++i) {
    if (skippable(lines[i].text)) continue;
    LineError fail = at(path, lines[i]);
    auto t = tokens(lines[i].text);
    if (t.size() < 10) fail("expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    toUint(t[0], fail, "IMAGE_ID");
    double q[4], tr[3];
    for (int k = 0; k < 4; ++k) q[k] = toDouble(t[1 + k], fail, "quaternion component");
    for (int k = 0; k < 3; ++k) tr[k] = toDouble(t[5 + k], fail, "translation component");
    uint64_t camId = toUint(t[8], fail, "CAMERA_ID");
    // The name is the rest of the line: file names may hold spaces.
    std::string name = afterTokens(lines[i].text, 9);
    auto cam = cams.find(camId);
    if (cam == cams.end()) fail("image '" + name + "' uses camera " + t[8] + ", which cameras.txt does not define");
    double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    // Text rounding leaves |q| within ~1e-6 of 1; anything far off is corruption, not rounding.
    if (std::fabs(norm - 1) > 1e-2) fail("quaternion is not unit length (|q| = " + std::to_string(norm) + ")");
    auto R = rotation(q[0] / norm, q[1] / norm, q[2] / norm, q[3] / norm);
    ColmapImage img{name, {}, &cam->second, fail.at};
    auto& m = img.c2w;
    for (int r = 0; r < 3; ++r) {
      // Row r of R^T is column r of R; negate the camera's y and z axes (columns 1 and 2).
      m[4 * r + 0] = R[0 * 3 + r];
      m[4 * r + 1] = -R[1 * 3 + r];
      m[4 * r + 2] = -R[2 * 3 + r];
      m[4 * r + 3] = -(R[0 * 3 + r] * tr[0] + R[1 * 3 + r] * tr[1] + R[2 * 3 + r] * tr[2]);
    }
    m[15] = 1;
    images.push_back(std::move(img));
    // The POINTS2D line follows (possibly empty); it must hold (X, Y, POINT3D_ID) triples.
    if (++i < lines.size() && tokens(lines[i].text).size() % 3 != 0)
      at(path, lines[i])("expected the POINTS2D line (X Y POINT3D_ID triples) after the image line");
  }
  if (images.empty()) throw Error("'" + path.string() + "' lists no images");
  return images;
}

// Per-axis 1st and 99th percentiles of points3D.txt, padded by 5% of the largest extent; false when
// there are fewer than 2 points or they span no volume.
bool pointsBox(const fs::path& path, std::array<double, 3>& lo, std::array<double, 3>& hi) {
  std::array<std::vector<double>, 3> xyz;
  for (const Line& line : readLines(path)) {
    if (skippable(line.text)) continue;
    LineError fail = at(path, line);
    auto t = tokens(line.text);
    if (t.size() < 8 || (t.size() - 8) % 2 != 0) fail("expected POINT3D_ID X Y Z R G B ERROR TRACK[] (IMAGE_ID POINT2D_IDX pairs)");
    toUint(t[0], fail, "POINT3D_ID");
    for (int k = 0; k < 3; ++k) xyz[k].push_back(toDouble(t[1 + k], fail, "point coordinate"));
  }
  const size_t n = xyz[0].size();
  if (n < 2) return false;
  double extent = 0;
  for (int k = 0; k < 3; ++k) {
    auto& v = xyz[k];
    std::sort(v.begin(), v.end());
    lo[k] = v[size_t(0.01 * double(n - 1) + 0.5)];
    hi[k] = v[size_t(0.99 * double(n - 1) + 0.5)];
    extent = std::max(extent, hi[k] - lo[k]);
  }
  if (!(extent > 0)) return false;
  for (int k = 0; k < 3; ++k) {
    lo[k] -= 0.05 * extent;
    hi[k] += 0.05 * extent;
  }
  return true;
}

}  // namespace

SceneSpec readColmap(const fs::path& modelDir, const fs::path& imagesDir, const DatasetOptions& options) {
  auto cams = readCameras(modelDir / "cameras.txt");
  auto images = readImages(modelDir / "images.txt", cams);
  // COLMAP numbers images in the order it registered them; the name order is stable across runs.
  std::stable_sort(images.begin(), images.end(), [](const auto& a, const auto& b) { return a.name < b.name; });

  std::array<double, 3> lo, hi;
  SceneSpec scene;
  scene.hasBox = true;
  std::error_code ec;
  if (fs::is_regular_file(modelDir / "points3D.txt", ec) && pointsBox(modelDir / "points3D.txt", lo, hi)) {
    scene.boxSource = "points3D";
  } else {
    std::vector<Camera> all;
    for (const auto& img : images) {
      FrameSpec f{img.at, {}, {}, img.camera->intrinsics, img.c2w};
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
  for (int k = 0; k < 3; ++k) {
    scene.box.min[k] = float((lo[k] - centre[k]) * s);
    scene.box.max[k] = float((hi[k] - centre[k]) * s);
  }

  std::vector<size_t> pick = holdoutIndices(images.size(), options.holdoutFraction, options.split);
  std::vector<bool> picked(images.size(), false);
  for (size_t i : pick) picked[i] = true;
  for (size_t i = 0; i < images.size(); ++i) {
    FrameSpec f;
    f.where = images[i].at;
    f.intrinsics = images[i].camera->intrinsics;
    f.c2w = images[i].c2w;
    for (int k = 0; k < 3; ++k) f.c2w[4 * k + 3] = (f.c2w[4 * k + 3] - centre[k]) * s;
    checkRigid(f.c2w, f.where);
    fs::path p = imagesDir / images[i].name;
    if (fs::is_regular_file(p, ec))
      f.image = p;
    else
      f.imageTried = p.string();
    (picked[i] ? scene.frames : scene.others).push_back(std::move(f));
  }
  return scene;
}

}  // namespace vknerf::nerf::detail

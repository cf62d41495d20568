// nerf_synthetic / instant-ngp / nerfstudio transforms*.json. The poses are camera-to-world in the
// OpenGL convention already, so they are only checked, never changed.
#include <algorithm>
#include <fstream>
#include <iterator>
#include <numbers>
#include <nlohmann/json.hpp>
#include <optional>

#include "io/dataset_loaders.h"
#include "vknerf/error.h"

namespace vknerf::nerf::detail {
namespace {

using nlohmann::json;

const char* const kSplits[] = {"train", "val", "test"};

struct JsonFile {
  fs::path path;
  json root;
  std::string name() const { return path.string(); }
};

[[noreturn]] void fieldError(const JsonFile& f, const std::string& field, const std::string& what) {
  throw Error(f.name() + ": field '" + field + "' " + what);
}

JsonFile readJson(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open '" + path.string() + "'");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  JsonFile f{path, {}};
  try {
    f.root = json::parse(text);
  } catch (const json::exception& e) {
    // Parse errors carry "at line L, column C"; a number overflow (1e999) names only the literal,
    // so its first occurrence in the text gives the position.
    std::string what = e.what();
    if (auto close = what.find("] "); what.rfind("[json.exception", 0) == 0 && close != std::string::npos)
      what = what.substr(close + 2);
    if (what.find(" at line ") == std::string::npos) {
      auto q0 = what.find('\''), q1 = what.rfind('\'');
      if (q0 != std::string::npos && q1 > q0 + 1) {
        if (size_t at = text.find(what.substr(q0 + 1, q1 - q0 - 1)); at != std::string::npos) {
          size_t line = 1 + size_t(std::count(text.begin(), text.begin() + long(at), '\n'));
          size_t column = at - (line > 1 ? text.rfind('\n', at) + 1 : 0) + 1;
          what = "at line " + std::to_string(line) + ", column " + std::to_string(column) + ": " + what;
        }
      }
    }
    throw Error(path.string() + ": invalid JSON: " + what);
  }
  if (!f.root.is_object()) throw Error(path.string() + ": invalid transforms file: the top level is not a JSON object");
  return f;
}

std::optional<double> optNumber(const JsonFile& f, const json& obj, const char* key, const std::string& prefix) {
  auto it = obj.find(key);
  if (it == obj.end() || it->is_null()) return std::nullopt;
  if (!it->is_number()) fieldError(f, prefix + key, "must be a number");
  double v = it->get<double>();
  if (!std::isfinite(v)) fieldError(f, prefix + key, "is not finite");
  return v;
}

// Intrinsics stated by `obj` (the file's top level or one frame) override those in `in`.
void readIntrinsics(const JsonFile& f, const json& obj, const std::string& prefix, Intrinsics& in) {
  auto angle = [&](const char* key) {
    auto a = optNumber(f, obj, key, prefix);
    if (a && !(*a > 0 && *a < std::numbers::pi)) fieldError(f, prefix + key, "must be in (0, pi) radians, got " + std::to_string(*a));
    return a;
  };
  auto positive = [&](const char* key) {
    auto v = optNumber(f, obj, key, prefix);
    if (v && !(*v > 0)) fieldError(f, prefix + key, "must be positive, got " + std::to_string(*v));
    return v;
  };
  auto size = [&](const char* key) -> std::optional<uint32_t> {
    auto v = positive(key);
    if (v && (*v != std::floor(*v) || *v > 1e6)) fieldError(f, prefix + key, "must be a whole number of pixels");
    return v ? std::optional<uint32_t>(uint32_t(*v)) : std::nullopt;
  };
  // A focal length stated here replaces an inherited angle and the other way round.
  if (auto a = angle("camera_angle_x")) in.angleX = *a, in.fx = NAN;
  if (auto a = angle("camera_angle_y")) in.angleY = *a, in.fy = NAN;
  if (auto v = positive("fl_x")) in.fx = *v;
  if (auto v = positive("fl_y")) in.fy = *v;
  if (auto v = optNumber(f, obj, "cx", prefix)) in.cx = *v;
  if (auto v = optNumber(f, obj, "cy", prefix)) in.cy = *v;
  if (auto v = size("w")) in.width = *v;
  if (auto v = size("h")) in.height = *v;
  for (const char* key : {"k1", "k2", "k3", "k4", "p1", "p2"})
    if (auto v = optNumber(f, obj, key, prefix); v && *v != 0)
      fieldError(f, prefix + key, "is nonzero: lens distortion is not handled (undistort the images first)");
  if (auto it = obj.find("camera_model"); it != obj.end()) {
    std::string model = it->is_string() ? it->get<std::string>() : "";
    if (model != "OPENCV" && model != "PINHOLE" && model != "SIMPLE_PINHOLE" && model != "PERSPECTIVE")
      fieldError(f, prefix + "camera_model", "'" + model + "' is not handled (pinhole cameras only)");
  }
}

std::array<double, 16> readMatrix(const JsonFile& f, const json& frame, const std::string& prefix) {
  const std::string field = prefix + "transform_matrix";
  auto it = frame.find("transform_matrix");
  if (it == frame.end()) fieldError(f, field, "is missing");
  const json& m = *it;
  if (!m.is_array() || (m.size() != 4 && m.size() != 3)) fieldError(f, field, "must be a 4x4 (or 3x4) array of numbers");
  std::array<double, 16> out{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  for (size_t r = 0; r < m.size(); ++r) {
    if (!m[r].is_array() || m[r].size() != 4) fieldError(f, field, "must be a 4x4 (or 3x4) array of numbers");
    for (size_t c = 0; c < 4; ++c) {
      if (!m[r][c].is_number()) fieldError(f, field, "must be a 4x4 (or 3x4) array of numbers");
      out[4 * r + c] = m[r][c].get<double>();
    }
  }
  return out;
}

// The image a frame names, relative to the JSON's folder; nerf_synthetic leaves the extension out.
void resolveImage(const JsonFile& f, const std::string& filePath, FrameSpec& spec) {
  fs::path base = f.path.parent_path() / filePath;
  std::error_code ec;
  spec.imageTried = base.string();
  if (fs::is_regular_file(base, ec)) {
    spec.image = base;
    return;
  }
  for (const char* ext : {".png", ".jpg", ".jpeg", ".PNG", ".JPG", ".JPEG"}) {
    fs::path p = base;
    p += ext;
    if (fs::is_regular_file(p, ec)) {
      spec.image = p;
      return;
    }
  }
  spec.imageTried += " (also with .png, .jpg, .jpeg)";
}

std::vector<FrameSpec> readFrames(const JsonFile& f) {
  Intrinsics global;
  readIntrinsics(f, f.root, "", global);
  auto it = f.root.find("frames");
  if (it == f.root.end()) fieldError(f, "frames", "is missing");
  if (!it->is_array()) fieldError(f, "frames", "must be an array");
  if (it->empty()) fieldError(f, "frames", "is empty");
  std::vector<FrameSpec> frames;
  for (size_t i = 0; i < it->size(); ++i) {
    const json& frame = (*it)[i];
    const std::string prefix = "frames[" + std::to_string(i) + "].";
    if (!frame.is_object()) fieldError(f, "frames[" + std::to_string(i) + "]", "must be an object");
    FrameSpec spec;
    spec.where = f.name() + ": frames[" + std::to_string(i) + "]";
    spec.intrinsics = global;
    readIntrinsics(f, frame, prefix, spec.intrinsics);
    auto fp = frame.find("file_path");
    if (fp == frame.end()) fieldError(f, prefix + "file_path", "is missing");
    if (!fp->is_string() || fp->get<std::string>().empty()) fieldError(f, prefix + "file_path", "must be a non-empty string");
    resolveImage(f, fp->get<std::string>(), spec);
    spec.c2w = readMatrix(f, frame, prefix);
    checkRigid(spec.c2w, spec.where);
    frames.push_back(std::move(spec));
  }
  return frames;
}

// "aabb", or instant-ngp's cube: ngp maps a point p of this file's frame to p * scale + offset (then
// cycles the axes, which leaves a cube a cube) and bounds the scene by the cube of side aabb_scale
// (at most 128, as ngp clamps it) centred at (0.5, 0.5, 0.5).
bool readBox(const JsonFile& f, Aabb& box, std::string& source, float& cubeSide) {
  const json& r = f.root;
  if (auto it = r.find("aabb"); it != r.end()) {
    const json& a = *it;
    auto bad = [&] { fieldError(f, "aabb", "must be [[min x, y, z], [max x, y, z]] with min < max"); };
    if (!a.is_array() || a.size() != 2 || !a[0].is_array() || !a[1].is_array() || a[0].size() != 3 || a[1].size() != 3) bad();
    for (int k = 0; k < 3; ++k) {
      if (!a[0][k].is_number() || !a[1][k].is_number()) bad();
      double lo = a[0][k].get<double>(), hi = a[1][k].get<double>();
      if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi)) bad();
      box.min[k] = float(lo);
      box.max[k] = float(hi);
    }
    source = "json aabb";
    return true;
  }
  auto aabbScale = optNumber(f, r, "aabb_scale", "");
  auto scale = optNumber(f, r, "scale", "");
  auto offsetIt = r.find("offset");
  if (!aabbScale && !scale && offsetIt == r.end()) return false;
  double side = aabbScale.value_or(1.0), s = scale.value_or(0.33);
  if (!(side > 0)) fieldError(f, "aabb_scale", "must be positive");
  if (!(s > 0)) fieldError(f, "scale", "must be positive");
  side = std::min(side, 128.0);
  cubeSide = float(side);
  double offset[3] = {0.5, 0.5, 0.5};
  if (offsetIt != r.end()) {
    const json& o = *offsetIt;
    if (!o.is_array() || o.size() != 3) fieldError(f, "offset", "must be an array of 3 numbers");
    for (int k = 0; k < 3; ++k) {
      if (!o[k].is_number() || !std::isfinite(o[k].get<double>())) fieldError(f, "offset", "must be an array of 3 numbers");
      offset[k] = o[k].get<double>();
    }
  }
  for (int k = 0; k < 3; ++k) {
    box.min[k] = float((0.5 - 0.5 * side - offset[k]) / s);
    box.max[k] = float((0.5 + 0.5 * side - offset[k]) / s);
  }
  source = "aabb_scale";
  return true;
}

std::optional<std::string> splitOfFileName(const fs::path& p) {
  for (const char* s : kSplits)
    if (p.filename() == std::string("transforms_") + s + ".json") return s;
  return std::nullopt;
}

void takeBox(const JsonFile& f, SceneSpec& scene) {
  if (!scene.hasBox) scene.hasBox = readBox(f, scene.box, scene.boxSource, scene.aabbScale);
}

// Split files beside the requested ones: their cameras only help place the scene box, so a flaw in
// one of them is left for the load of that split to report.
void addOthers(const fs::path& folder, const std::vector<std::string>& taken, SceneSpec& scene) {
  for (const char* s : kSplits) {
    if (std::find(taken.begin(), taken.end(), s) != taken.end()) continue;
    fs::path p = folder / (std::string("transforms_") + s + ".json");
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) continue;
    try {
      JsonFile f = readJson(p);
      for (auto& fr : readFrames(f)) scene.others.push_back(std::move(fr));
      takeBox(f, scene);
    } catch (const Error&) {
    }
  }
}

}  // namespace

SceneSpec readTransformsJson(const fs::path& target, const DatasetOptions& options) {
  SceneSpec scene;
  std::error_code ec;
  const bool isFolder = fs::is_directory(target, ec);
  const fs::path folder = isFolder ? target : target.parent_path();
  std::optional<std::string> fileSplit = isFolder ? std::nullopt : splitOfFileName(target);

  if (fileSplit || (isFolder && fs::is_regular_file(folder / "transforms_train.json", ec))) {
    // Split files: the split is the file.
    std::vector<std::string> wanted;
    if (fileSplit)
      wanted = {*fileSplit};
    else if (options.split == "all")
      for (const char* s : kSplits) {
        if (fs::is_regular_file(folder / (std::string("transforms_") + s + ".json"), ec)) wanted.push_back(s);
      }
    else
      wanted = {options.split};
    for (const std::string& s : wanted) {
      fs::path p = folder / ("transforms_" + s + ".json");
      if (!fs::is_regular_file(p, ec)) throw Error("'" + p.string() + "' not found (split '" + s + "')");
      JsonFile f = readJson(p);
      for (auto& fr : readFrames(f)) scene.frames.push_back(std::move(fr));
      takeBox(f, scene);
    }
    addOthers(folder, wanted, scene);
    return scene;
  }

  // One file for the whole scene: hold out evenly spaced frames.
  JsonFile f = readJson(isFolder ? folder / "transforms.json" : target);
  std::vector<FrameSpec> all = readFrames(f);
  takeBox(f, scene);
  std::vector<size_t> pick = holdoutIndices(all.size(), options.holdoutFraction, options.split);
  std::vector<bool> picked(all.size(), false);
  for (size_t i : pick) picked[i] = true;
  for (size_t i = 0; i < all.size(); ++i) (picked[i] ? scene.frames : scene.others).push_back(std::move(all[i]));
  return scene;
}

}  // namespace vknerf::nerf::detail

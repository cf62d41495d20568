// nerf_synthetic / instant-ngp / nerfstudio transforms*.json. The poses are camera-to-world in the
// OpenGL convention already, so they are only checked, never changed. Intrinsics and the lens may be
// stated at the top level, per frame, or both (a frame's keys override the top level's).
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <numbers>
#include <nlohmann/json.hpp>
#include <optional>

#include "io/dataset/dataset_loaders.h"
#include "io/dataset/load_note.h"
#include "io/file/json_file.h"
#include "vknerf/error.h"

namespace vknerf::io::detail {
namespace {

using nlohmann::json;

const char* const kSplits[] = {"train", "val", "test"};

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
}

// The lens keys of the file's top level or of one frame (a frame's override the top level's), each
// with the field that stated it, for messages; resolveLens() turns them into a Lens.
struct LensKey {
  double value = 0;
  std::string field;
};
struct LensKeys {
  LensKey k1, k2, k3, k4, p1, p2;
  std::optional<bool> fisheye;  // instant-ngp's is_fisheye
  std::string fisheyeField;
  std::optional<std::string> model;  // nerfstudio's camera_model
  std::string modelField;
};

void readLensKeys(const JsonFile& f, const json& obj, const std::string& prefix, LensKeys& keys) {
  const std::pair<const char*, LensKey*> coefficients[] = {{"k1", &keys.k1}, {"k2", &keys.k2}, {"k3", &keys.k3},
                                                           {"k4", &keys.k4}, {"p1", &keys.p1}, {"p2", &keys.p2}};
  for (const auto& [key, slot] : coefficients)
    if (auto v = optNumber(f, obj, key, prefix)) {
      if (!std::isfinite(float(*v))) fieldError(f, prefix + key, "is not finite as a 32-bit float");
      *slot = {*v, prefix + key};
    }
  if (auto it = obj.find("is_fisheye"); it != obj.end() && !it->is_null()) {
    if (!it->is_boolean()) fieldError(f, prefix + "is_fisheye", "must be true or false");
    keys.fisheye = it->get<bool>();
    keys.fisheyeField = prefix + "is_fisheye";
  }
  if (auto it = obj.find("camera_model"); it != obj.end() && !it->is_null()) {
    if (!it->is_string()) fieldError(f, prefix + "camera_model", "must be a string");
    keys.model = it->get<std::string>();
    keys.modelField = prefix + "camera_model";
  }
}

// nerfstudio's camera_model names the model: PINHOLE (or SIMPLE_PINHOLE, PERSPECTIVE), OPENCV (k1
// k2 k3 radial, p1 p2 tangential), OPENCV_FISHEYE (k1..k4). Without it, instant-ngp's is_fisheye
// picks the fisheye, else any nonzero coefficient the radial-tangential model. instant-ngp's own
// radial-tangential lens has k1 k2 p1 p2 only (its k3/k4 land in the p1/p2 slots and are overwritten
// by them); k3 here is OpenCV's and nerfstudio's r^6 term, and k4 outside the fisheye (nerfstudio's
// r^8 term, which OpenCV's model lacks) is refused rather than misread. A lens whose coefficients
// are all zero is a pinhole.
Lens resolveLens(const JsonFile& f, const LensKeys& k) {
  enum class Kind { Unstated, Pinhole, OpenCV, Fisheye } kind = Kind::Unstated;
  if (k.model) {
    const std::string& m = *k.model;
    if (m == "PINHOLE" || m == "SIMPLE_PINHOLE" || m == "PERSPECTIVE")
      kind = Kind::Pinhole;
    else if (m == "OPENCV")
      kind = Kind::OpenCV;
    else if (m == "OPENCV_FISHEYE")
      kind = Kind::Fisheye;
    else
      fieldError(f, k.modelField, "'" + m + "' is not handled (PINHOLE, OPENCV or OPENCV_FISHEYE)");
    if (k.fisheye && *k.fisheye != (kind == Kind::Fisheye))
      fieldError(f, k.fisheyeField, "contradicts " + k.modelField + " '" + m + "'");
  } else if (k.fisheye && *k.fisheye) {
    kind = Kind::Fisheye;
  }
  auto zero = [&](const LensKey& key, const std::string& why) {
    if (key.value != 0) fieldError(f, key.field, "is nonzero: " + why);
  };
  Lens l;
  if (kind == Kind::Pinhole) {
    for (const LensKey* key : {&k.k1, &k.k2, &k.k3, &k.k4, &k.p1, &k.p2})
      zero(*key, k.modelField + " '" + *k.model + "' has no distortion");
    return l;
  }
  if (kind == Kind::Fisheye) {
    zero(k.p1, "the fisheye model has no tangential terms");
    zero(k.p2, "the fisheye model has no tangential terms");
    l.model = LensModel::Fisheye;
    l.k4 = float(k.k4.value);
  } else {
    zero(k.k4, "k4 belongs to the fisheye model (is_fisheye or camera_model OPENCV_FISHEYE); the radial-tangential model reads k1 k2 k3 p1 p2");
    l.model = LensModel::OpenCV;
    l.p1 = float(k.p1.value);
    l.p2 = float(k.p2.value);
  }
  l.k1 = float(k.k1.value);
  l.k2 = float(k.k2.value);
  l.k3 = float(k.k3.value);
  if (l.k1 == 0 && l.k2 == 0 && l.k3 == 0 && l.k4 == 0 && l.p1 == 0 && l.p2 == 0) l.model = LensModel::Pinhole;
  return l;
}

// `base` itself, or with an image extension added (nerf_synthetic leaves it out); empty if neither.
fs::path existingImage(const fs::path& base) {
  std::error_code ec;
  if (fs::is_regular_file(base, ec)) return base;
  for (const char* ext : {".png", ".jpg", ".jpeg", ".PNG", ".JPG", ".JPEG"}) {
    fs::path p = base;
    p += ext;
    if (fs::is_regular_file(p, ec)) return p;
  }
  return {};
}

// How many absolute file_paths that do not exist here (written on the author's machine, and shared
// as they were) were found by their base name beside the JSON, and how many in its images/ folder.
struct Substitutes {
  size_t beside = 0, inImages = 0;
};

// The image a frame names, relative to the JSON's folder. An absolute path that exists is taken as
// it is; one that does not falls back to the file of its name beside the JSON, then in images/.
void resolveImage(const JsonFile& f, const std::string& filePath, FrameSpec& spec, Substitutes& substitutes) {
  const fs::path folder = f.path.parent_path(), base = folder / filePath;
  spec.image = existingImage(base);
  const fs::path name = fs::path(filePath).filename();
  if (!spec.image.empty()) return;
  if (!fs::path(filePath).is_absolute() || name.empty()) {
    spec.imageTried = base.string() + " (also with .png, .jpg, .jpeg)";
    return;
  }
  if (spec.image = existingImage(folder / name); !spec.image.empty()) {
    ++substitutes.beside;
    return;
  }
  if (spec.image = existingImage(folder / "images" / name); !spec.image.empty()) {
    ++substitutes.inImages;
    return;
  }
  spec.imageTried = "file_path '" + filePath + "' does not exist here, nor does " + name.string() +
                    " (also with .png, .jpg, .jpeg) beside " + f.name() + " or in " + (folder / "images").string() + "/";
}

// One line for the file's substitutes, however many frames they are.
void noteSubstitutes(const JsonFile& f, const Substitutes& s) {
  const size_t count = s.beside + s.inImages;
  if (count == 0) return;
  const std::string images = (f.path.parent_path() / "images").string() + "/";
  const std::string where = s.inImages == 0 ? "beside it"
                            : s.beside == 0 ? "in " + images
                                            : "beside it (" + std::to_string(s.beside) + ") and in " + images + " (" +
                                                  std::to_string(s.inImages) + ")";
  const char* entries = count == 1 ? " file_path entry is an absolute path that does" : " file_path entries are absolute paths that do";
  noteOnce(f.name() + ": " + std::to_string(count) + entries + " not exist here; using the files of those names " + where);
}

std::vector<FrameSpec> readFrames(const JsonFile& f) {
  Intrinsics global;
  readIntrinsics(f, f.root, "", global);
  LensKeys globalLens;
  readLensKeys(f, f.root, "", globalLens);
  auto it = f.root.find("frames");
  if (it == f.root.end()) fieldError(f, "frames", "is missing");
  if (!it->is_array()) fieldError(f, "frames", "must be an array");
  if (it->empty()) fieldError(f, "frames", "is empty");
  std::vector<FrameSpec> frames;
  Substitutes substitutes;
  for (size_t i = 0; i < it->size(); ++i) {
    const json& frame = (*it)[i];
    const std::string prefix = "frames[" + std::to_string(i) + "].";
    if (!frame.is_object()) fieldError(f, "frames[" + std::to_string(i) + "]", "must be an object");
    FrameSpec spec;
    spec.where = f.name() + ": frames[" + std::to_string(i) + "]";
    spec.intrinsics = global;
    readIntrinsics(f, frame, prefix, spec.intrinsics);
    LensKeys lens = globalLens;
    readLensKeys(f, frame, prefix, lens);
    spec.intrinsics.lens = resolveLens(f, lens);
    auto fp = frame.find("file_path");
    if (fp == frame.end()) fieldError(f, prefix + "file_path", "is missing");
    if (!fp->is_string() || fp->get<std::string>().empty()) fieldError(f, prefix + "file_path", "must be a non-empty string");
    resolveImage(f, fp->get<std::string>(), spec, substitutes);
    spec.c2w = readMatrixField(f, frame, "transform_matrix", prefix);
    checkRigid(spec.c2w, spec.where);
    frames.push_back(std::move(spec));
  }
  noteSubstitutes(f, substitutes);
  return frames;
}

// "aabb", or instant-ngp's cube: ngp maps a point p of this file's frame to p * scale + offset (then
// cycles the axes, which leaves a cube a cube) and bounds the scene by the cube of side aabb_scale
// (at most 128: ngp clamps a larger one, which is refused here) centred at (0.5, 0.5, 0.5).
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
  // instant-ngp clamps a larger cube to 128 without a word; trained that way the file's box would
  // not be the one it states, so it is refused rather than clamped.
  if (side > 128.0) {
    char got[32];
    std::snprintf(got, sizeof got, "%g", side);
    fieldError(f, "aabb_scale", std::string("must be at most 128 (instant-ngp's largest cube), got ") + got);
  }
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
      JsonFile f = readJson(p, "transforms file");
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
      JsonFile f = readJson(p, "transforms file");
      for (auto& fr : readFrames(f)) scene.frames.push_back(std::move(fr));
      takeBox(f, scene);
    }
    addOthers(folder, wanted, scene);
    return scene;
  }

  // One file for the whole scene: hold out evenly spaced frames.
  JsonFile f = readJson(isFolder ? folder / "transforms.json" : target, "transforms file");
  std::vector<FrameSpec> all = readFrames(f);
  takeBox(f, scene);
  std::vector<size_t> pick = holdoutIndices(all.size(), options.holdoutFraction, options.split);
  std::vector<bool> picked(all.size(), false);
  for (size_t i : pick) picked[i] = true;
  for (size_t i = 0; i < all.size(); ++i) (picked[i] ? scene.frames : scene.others).push_back(std::move(all[i]));
  return scene;
}

}  // namespace vknerf::io::detail

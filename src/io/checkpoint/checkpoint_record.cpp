#include "io/checkpoint/checkpoint_record.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "io/checkpoint/config_json.h"
#include "vknerf/error.h"

namespace vknerf::io {
namespace {

using nlohmann::json;

Aabb boxFromJson(const json& j) {
  Aabb b;
  b.min = j.at("min").get<std::array<float, 3>>();
  b.max = j.at("max").get<std::array<float, 3>>();
  return b;
}

// The checkpoint's scene box, within `tolerance` of its extent (at least 1) of `box`.
bool sameBox(const Aabb& a, const Aabb& b, float tolerance) {
  for (int k = 0; k < 3; ++k) {
    const float tol = tolerance * std::max(1.0f, std::fabs(a.max[k] - a.min[k]));
    if (!(std::fabs(a.min[k] - b.min[k]) <= tol) || !(std::fabs(a.max[k] - b.max[k]) <= tol)) return false;
  }
  return true;
}

std::string boxText(const Aabb& b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "[%g %g %g]..[%g %g %g]", b.min[0], b.min[1], b.min[2], b.max[0], b.max[1], b.max[2]);
  return buf;
}

const std::pair<LensModel, const char*> kLensModels[] = {
    {LensModel::Pinhole, "pinhole"}, {LensModel::OpenCV, "opencv"}, {LensModel::Fisheye, "fisheye"}};

// Every coefficient of a Lens by its key, so that writing and reading name them alike.
template <class L> auto lensCoefficients(L& l) {
  return std::array<std::pair<const char*, decltype(&l.k1)>, 8>{
      {{"k1", &l.k1}, {"k2", &l.k2}, {"k3", &l.k3}, {"k4", &l.k4}, {"k5", &l.k5}, {"k6", &l.k6}, {"p1", &l.p1}, {"p2", &l.p2}}};
}

// A float as JSON: the double it converts to exactly, printed by nlohmann as the shortest text that
// parses back to that double, so that the float reads back bit for bit.
json cameraToJson(const TrainedCamera& t) {
  const Camera& c = t.camera;
  json lens = json::object();
  for (const auto& [model, name] : kLensModels)
    if (model == c.lens.model) lens["model"] = name;
  for (const auto& [key, value] : lensCoefficients(c.lens)) lens[key] = double(*value);
  json c2w = json::array();
  for (float v : c.c2w) c2w.push_back(double(v));
  return {{"name", t.name}, {"width", c.width}, {"height", c.height}, {"fx", double(c.fx)}, {"fy", double(c.fy)},
          {"cx", double(c.cx)}, {"cy", double(c.cy)}, {"c2w", std::move(c2w)}, {"lens", std::move(lens)}};
}

// Reads one recorded camera; every failure names the file and the field ("training_cameras[3].fx").
struct CameraReader {
  const std::string& path;
  std::string prefix;

  [[noreturn]] void fail(const std::string& field, const std::string& why) const {
    throw Error(path + ": checkpoint " + prefix + (field.empty() ? "" : "." + field) + " " + why);
  }
  const json& at(const json& obj, const char* key, const std::string& field) const {
    const auto it = obj.find(key);
    if (it == obj.end()) fail(field, "is missing");
    return *it;
  }
  // A value written from a float: finite, and within float's range (a larger double has no float).
  float number(const json& v, const std::string& field) const {
    if (!v.is_number()) fail(field, "must be a number");
    const double d = v.get<double>();
    if (!(std::fabs(d) <= double(std::numeric_limits<float>::max()))) fail(field, "is not a finite 32-bit float");
    return float(d);
  }
  float numberAt(const json& obj, const char* key) const { return number(at(obj, key, key), std::string(key)); }
  uint32_t size(const json& obj, const char* key) const {
    const json& v = at(obj, key, key);
    if (!v.is_number_unsigned() || v.get<uint64_t>() == 0 || v.get<uint64_t>() > UINT32_MAX)
      fail(key, "must be a whole number of pixels from 1 to 4294967295");
    return uint32_t(v.get<uint64_t>());
  }

  TrainedCamera read(const json& j) const {
    if (!j.is_object()) fail("", "must be an object");
    TrainedCamera t;
    const json& name = at(j, "name", "name");
    if (!name.is_string()) fail("name", "must be a string");
    t.name = name.get<std::string>();
    Camera& c = t.camera;
    c.width = size(j, "width");
    c.height = size(j, "height");
    c.fx = numberAt(j, "fx");
    c.fy = numberAt(j, "fy");
    if (!(c.fx > 0) || !(c.fy > 0)) fail(c.fx > 0 ? "fy" : "fx", "must be positive");
    c.cx = numberAt(j, "cx");
    c.cy = numberAt(j, "cy");
    const json& c2w = at(j, "c2w", "c2w");
    if (!c2w.is_array() || c2w.size() != 16) fail("c2w", "must be an array of 16 numbers (row-major 4x4)");
    for (size_t i = 0; i < 16; ++i) c.c2w[i] = number(c2w[i], "c2w[" + std::to_string(i) + "]");
    const json& lens = at(j, "lens", "lens");
    if (!lens.is_object()) fail("lens", "must be an object");
    const json& model = at(lens, "model", "lens.model");
    bool known = false;
    for (const auto& [m, n] : kLensModels)
      if (model.is_string() && model.get<std::string>() == n) c.lens.model = m, known = true;
    if (!known) fail("lens.model", "must be \"pinhole\", \"opencv\" or \"fisheye\"");
    for (const auto& [key, value] : lensCoefficients(c.lens))
      *value = number(at(lens, key, std::string("lens.") + key), std::string("lens.") + key);
    return t;
  }
};

}  // namespace

std::string CheckpointRecord::write(const TrainConfig& config, uint32_t step, const Aabb& bounds, const SceneRecord& scene,
                                    const std::vector<TrainedCamera>& cameras) {
  json j = {{"format", "vknerf"}, {"config", toJson(config)}, {"step", step},
            {"bounds", {{"min", bounds.min}, {"max", bounds.max}}},
            {"scene", {{"cameras", scene.cameras}, {"width", scene.width}, {"height", scene.height}}}};
  json& list = j["training_cameras"] = json::array();
  for (const TrainedCamera& c : cameras) list.push_back(cameraToJson(c));
  return j.dump(2);
}

std::vector<TrainedCamera> CheckpointRecord::trainingCameras() const {
  const auto it = j_.find("training_cameras");
  if (it == j_.end())
    throw Error(path_ + ": checkpoint has no training_cameras (it was written before checkpoints recorded the training "
                        "cameras; train --resume on its scene saves them)");
  if (!it->is_array()) throw Error(path_ + ": checkpoint training_cameras must be an array");
  std::vector<TrainedCamera> cameras;
  for (size_t i = 0; i < it->size(); ++i)
    cameras.push_back(CameraReader{path_, "training_cameras[" + std::to_string(i) + "]"}.read((*it)[i]));
  return cameras;
}

CheckpointRecord::CheckpointRecord(const Checkpoint& ck) : path_(ck.path) {
  try {
    j_ = json::parse(ck.config);
  } catch (const json::exception& e) {
    throw Error(path_ + ": checkpoint config is not valid JSON: " + e.what());
  }
}

TrainConfig CheckpointRecord::config() const {
  try {
    return trainConfigFromJson(j_.at("config"), path_);
  } catch (const json::exception& e) {
    throw Error(path_ + ": checkpoint config: " + e.what());
  }
}

bool CheckpointRecord::sameModel(const TrainConfig& config) const { return toJson(this->config())["model"] == toJson(config)["model"]; }

Aabb CheckpointRecord::bounds() const {
  try {
    return boxFromJson(j_.at("bounds"));
  } catch (const json::exception& e) {
    throw Error(path_ + ": checkpoint bounds: " + e.what());
  }
}

uint32_t CheckpointRecord::step() const {
  try {
    return j_.at("step").get<uint32_t>();
  } catch (const json::exception& e) {
    throw Error(path_ + ": checkpoint step: " + e.what());
  }
}

std::optional<uint32_t> CheckpointRecord::trainingPhotoCount() const {
  if (!j_.contains("scene")) return std::nullopt;
  try {
    return j_.at("scene").at("cameras").get<uint32_t>();
  } catch (const json::exception& e) {
    throw Error(path_ + ": checkpoint scene.cameras: " + e.what());
  }
}

void CheckpointRecord::checkScene(const SceneFacts& scene) const {
  const std::string& path = path_;
  try {
    const Aabb saved = boxFromJson(j_.at("bounds"));
    if (!sameBox(saved, scene.box, scene.boxTolerance))
      throw Error(path + ": checkpoint scene box " + boxText(saved) + " differs from this dataset's " +
                  boxText(scene.box) + "; it was trained on another scene");
    if (!j_.contains("scene") || !scene.cameras) return;  // checkpoints written before the scene record have the box alone
    const json& sc = j_.at("scene");
    const uint32_t n = sc.at("cameras"), w = sc.at("width"), h = sc.at("height");
    if (!scene.imageSize && n != *scene.cameras)
      throw Error(path + ": checkpoint was trained on " + std::to_string(n) + " images, this dataset's training split has " +
                  std::to_string(*scene.cameras) + "; it was trained on another scene");
    if (scene.imageSize && (n != *scene.cameras || w != scene.imageSize->first || h != scene.imageSize->second))
      throw Error(path + ": checkpoint was trained on " + std::to_string(n) + " images of " + std::to_string(w) + "x" +
                  std::to_string(h) + ", this dataset has " + std::to_string(*scene.cameras) + " of " +
                  std::to_string(scene.imageSize->first) + "x" + std::to_string(scene.imageSize->second) +
                  "; it was trained on another scene or --downscale");
  } catch (const json::exception& e) {
    throw Error(path + ": checkpoint scene record: " + e.what());
  }
}

}  // namespace vknerf::io

#include "io/checkpoint/checkpoint_record.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "io/checkpoint/config_json.h"
#include "vknerf/error.h"

namespace vknerf::nerf {
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

}  // namespace

std::string CheckpointRecord::write(const TrainConfig& config, uint32_t step, const Aabb& bounds, const SceneRecord& scene) {
  json j = {{"format", "vknerf"}, {"config", toJson(config)}, {"step", step},
            {"bounds", {{"min", bounds.min}, {"max", bounds.max}}},
            {"scene", {{"cameras", scene.cameras}, {"width", scene.width}, {"height", scene.height}}}};
  return j.dump(2);
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

std::optional<uint32_t> CheckpointRecord::trainingCameras() const {
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

}  // namespace vknerf::nerf

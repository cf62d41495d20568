#pragma once
// The JSON record a checkpoint carries besides its arrays: the format, the training configuration,
// the step, the scene box, the scene it was trained on (camera count and first image's size) and
// the training cameras. The one place that knows its layout: the Trainer writes it, Model::load,
// Trainer::resume, checkTrainedOn and Model::trainingCameras read it. Every field is read when
// asked, so a checkpoint written before the scene record (the box alone) or before the training
// cameras still loads; a missing or mistyped field throws vknerf::Error naming the file and the
// field.
//
//   "training_cameras": [{"name": "scene/./train/r_0.png", "width": 200, "height": 200,
//                         "fx": 277.1, "fy": 277.1, "cx": 100, "cy": 100,
//                         "c2w": [16 numbers, row-major, OpenGL convention as vknerf::Camera],
//                         "lens": {"model": "pinhole" | "opencv" | "fisheye",
//                                  "k1": 0, "k2": 0, "k3": 0, "k4": 0, "k5": 0, "k6": 0, "p1": 0, "p2": 0}}, ...]
//
// Each float is stored as the double it converts to exactly, which nlohmann prints as the shortest
// text that reads back to that double: a camera reads back bit for bit.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/checkpoint/checkpoint.h"
#include "vknerf/camera.h"
#include "vknerf/config.h"

namespace vknerf::io {

// The training set a checkpoint was fitted to, as recorded.
struct SceneRecord {
  uint32_t cameras = 0, width = 0, height = 0;
};

// What a scene shows of itself for the checks against a checkpoint's record.
struct SceneFacts {
  Aabb box;
  float boxTolerance = 1e-4f;  // float printing precision
  std::optional<uint32_t> cameras;                          // the training split's camera count
  std::optional<std::pair<uint32_t, uint32_t>> imageSize;  // its first image's size
};

class CheckpointRecord {
 public:
  // The record's text, as Checkpoint::config stores it.
  static std::string write(const TrainConfig& config, uint32_t step, const Aabb& bounds, const SceneRecord& scene,
                           const std::vector<TrainedCamera>& cameras);
  // Parses the record of `ck` (loaded from ck.path).
  explicit CheckpointRecord(const Checkpoint& ck);

  TrainConfig config() const;
  // Whether `config` trains the same model as the recorded one (the model part of the
  // configuration, as stored, is the same; training settings may differ).
  bool sameModel(const TrainConfig& config) const;
  Aabb bounds() const;
  uint32_t step() const;
  // The number of training photos (scene.cameras); none in a checkpoint written before the scene record.
  std::optional<uint32_t> trainingPhotoCount() const;
  // Weights fitted to another scene would train or render inside this scene's box: throws naming
  // the checkpoint when `scene` is not the one it was trained on.
  void checkScene(const SceneFacts& scene) const;
  // The training cameras in training order. Throws naming the file and "training_cameras" when the
  // checkpoint was written before they were recorded, and the camera's field when one is missing,
  // mistyped or out of range (a size of 0, a focal length <= 0, a value that is not a finite float).
  std::vector<TrainedCamera> trainingCameras() const;

 private:
  std::string path_;
  nlohmann::json j_;
};

}  // namespace vknerf::io

// writeTransformsJson: cameras as the transforms.json that transforms_json.cpp reads back.
#include <nlohmann/json.hpp>

#include "vknerf/error.h"
#include "vknerf/file_output.h"
#include "vknerf/transforms_file.h"

namespace vknerf {
namespace {

using nlohmann::json;

// A float widened exactly: nlohmann prints a double as the shortest text that parses back to it.
json number(float v) { return double(v); }

std::string cameraName(size_t i, const TrainedCamera& t) {
  return "camera " + std::to_string(i) + (t.name.empty() ? "" : " ('" + t.name + "')");
}

// nerfstudio's camera_model and coefficients, which the loader reads back as the same Lens.
void putLens(json& frame, const Lens& l, const std::string& camera) {
  switch (l.model) {
    case LensModel::Pinhole:
      frame["camera_model"] = "PINHOLE";
      return;
    case LensModel::Fisheye:
      frame["camera_model"] = "OPENCV_FISHEYE";
      for (const auto& [key, v] : {std::pair{"k1", l.k1}, {"k2", l.k2}, {"k3", l.k3}, {"k4", l.k4}}) frame[key] = number(v);
      return;
    case LensModel::OpenCV:
      for (const auto& [key, v] : {std::pair{"k4", l.k4}, {"k5", l.k5}, {"k6", l.k6}})
        if (v != 0)
          throw Error(camera + ": its OpenCV lens has " + key + " = " + std::to_string(v) +
                      "; transforms.json has no key for OpenCV's rational terms k4 k5 k6 (nerfstudio's k4 is another term)");
      frame["camera_model"] = "OPENCV";
      for (const auto& [key, v] : {std::pair{"k1", l.k1}, {"k2", l.k2}, {"k3", l.k3}, {"p1", l.p1}, {"p2", l.p2}})
        frame[key] = number(v);
      return;
  }
  throw Error(camera + ": unknown lens model " + std::to_string(uint32_t(l.model)));
}

}  // namespace

std::string transformsJson(const std::vector<TrainedCamera>& cameras) {
  json frames = json::array();
  for (size_t i = 0; i < cameras.size(); ++i) {
    const Camera& c = cameras[i].camera;
    json frame = json::object();
    if (!cameras[i].name.empty()) frame["file_path"] = cameras[i].name;
    json rows = json::array();
    for (int r = 0; r < 4; ++r)
      rows.push_back({number(c.c2w[4 * r]), number(c.c2w[4 * r + 1]), number(c.c2w[4 * r + 2]), number(c.c2w[4 * r + 3])});
    frame["transform_matrix"] = std::move(rows);
    frame["w"] = c.width;
    frame["h"] = c.height;
    frame["fl_x"] = number(c.fx);
    frame["fl_y"] = number(c.fy);
    frame["cx"] = number(c.cx);
    frame["cy"] = number(c.cy);
    putLens(frame, c.lens, cameraName(i, cameras[i]));
    frames.push_back(std::move(frame));
  }
  return json{{"frames", std::move(frames)}}.dump(2) + "\n";
}

void writeTransformsJson(const std::string& path, const std::vector<TrainedCamera>& cameras) {
  std::string text;
  try {
    text = transformsJson(cameras);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  writeFileAtomically(path, text);
}

}  // namespace vknerf

#pragma once
// A COLMAP model as its files state it, whichever form they take (text: colmap_text.cpp, binary:
// colmap_binary.cpp). The readers only parse and check the layout; colmap_scene.cpp turns the model
// into a SceneSpec (camera models, poses, scene box), so both forms mean exactly the same.
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "io/colmap/colmap_camera.h"
#include "io/dataset/dataset_loaders.h"

namespace vknerf::io::detail {

struct ColmapCamera {
  const ColmapCameraModel* model = nullptr;
  uint64_t width = 0, height = 0;
  std::vector<double> params;  // as many as the file holds (the text form may hold the wrong number)
  std::string where;           // names the record in messages: "cameras.txt:3", "cameras.bin: camera 2 (record 2 of 3)"
};

struct ColmapImage {
  std::string name;            // the image file, relative to the images folder
  std::array<double, 4> q{};   // world-to-camera rotation (w, x, y, z), OpenCV camera axes, finite
  std::array<double, 3> t{};   // world-to-camera translation, finite
  uint64_t cameraId = 0;
  std::string where;
};

struct ColmapModel {
  fs::path camerasFile, imagesFile;            // for messages
  std::map<uint64_t, ColmapCamera> cameras;    // by CAMERA_ID
  std::vector<ColmapImage> images;             // in file order
  std::vector<std::array<double, 3>> points;   // points3D coordinates, finite; empty without the file

  // Throws (naming the record) when `id` is already defined.
  void addCamera(uint64_t id, ColmapCamera camera);
};

// Readers of the files in `modelDir`; points3D.{txt,bin} is optional. Throw vknerf::Error naming
// the file and the line or record.
ColmapModel readColmapText(const fs::path& modelDir);
ColmapModel readColmapBinary(const fs::path& modelDir);

}  // namespace vknerf::io::detail

#pragma once
// Cameras as an instant-ngp / nerfstudio transforms.json (vknerf export cameras), in the keys that
// vknerf's own loader reads (vknerf/dataset.h), every value per frame:
//
//   {"frames": [{"file_path": "images/a.png",
//                "transform_matrix": [[4 numbers], [4], [4], [0, 0, 0, 1]],  camera-to-world, OpenGL
//                "w": 200, "h": 200, "fl_x": 277.1, "fl_y": 277.1, "cx": 100, "cy": 100,
//                "camera_model": "PINHOLE" | "OPENCV" with k1 k2 k3 p1 p2 | "OPENCV_FISHEYE" with k1..k4},
//               ...]}
//
// Each float is written as the double it converts to exactly (the shortest text that reads back to
// it), so the loader reads back the same floats.
#include <string>
#include <vector>

#include "vknerf/camera.h"

namespace vknerf {

// The file's text. A camera's name becomes its frame's file_path as it is (the loader reads a
// relative one from the file's folder); a camera without a name gets no file_path. Throws
// vknerf::Error naming the camera when its lens has OpenCV's rational terms (k4 k5 k6, from COLMAP's
// FULL_OPENCV), which transforms.json has no key for: nerfstudio's k4 is another term.
std::string transformsJson(const std::vector<TrainedCamera>& cameras);

// transformsJson written atomically (vknerf/file_output.h); errors name `path`.
void writeTransformsJson(const std::string& path, const std::vector<TrainedCamera>& cameras);

}  // namespace vknerf

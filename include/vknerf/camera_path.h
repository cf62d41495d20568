#pragma once
// A camera path to render: nerfstudio's camera path JSON (what its viewer's "Render" panel exports
// and ns-render reads), in the dataset's world frame:
//   { "render_width": W, "render_height": H, "fps": F, "seconds": S (optional),
//     "camera_type": "perspective" (optional; the only type read),
//     "camera_path": [ { "camera_to_world": [16 numbers, row-major 4x4, OpenGL convention],
//                        "fov": vertical field of view in degrees }, ... ] }
// One camera per entry of camera_path: nerfstudio writes the interpolated frames, fps * seconds of them.
#include <string>
#include <vector>

#include "vknerf/camera.h"

namespace vknerf {

struct CameraPath {
  std::vector<Camera> cameras;  // pinhole, principal point at the image centre
  double fps = 24;
};

// Throws vknerf::Error naming the file and the field for anything missing, malformed, not finite as
// a float, or out of range (sizes 1..16384, fov in (0, 180), fps in (0, 1000], a rigid pose).
CameraPath loadCameraPath(const std::string& path);

}  // namespace vknerf

#pragma once
// instant-ngp's camera path (base_cam.json; the format is described in vknerf/camera_path.h): its
// keyframes, the B-spline run.py samples them with, and the way back from instant-ngp's internal
// frame to the dataset's. Split out so the tests can check each step on its own.
#include <array>
#include <span>
#include <string>
#include <vector>

#include "io/file/json_file.h"
#include "vknerf/camera_path.h"

namespace vknerf::io::detail {

struct NgpKeyframe {
  std::array<double, 4> R{0, 0, 0, 1};  // quaternion, x y z w (Eigen's coefficient order)
  std::array<double, 3> T{};
  double fov = 50;  // vertical, degrees
};

// instant-ngp's map from the dataset's frame to its own: p -> p * scale + offset, then axes cycled.
struct NgpFrame {
  double scale = 0.33;
  std::array<double, 3> offset{0.5, 0.5, 0.5};
  std::string source = "instant-ngp's defaults";
};

// The keyframes of f's "path"; throws naming the file and the field (a missing or non-unit R, a
// missing T, fov outside (0, 180), an empty path, the newer timed format).
std::vector<NgpKeyframe> readNgpKeyframes(const JsonFile& f);

// The path at t in [0, 1], as instant-ngp's CameraPath::eval_camera_path: the uniform cubic
// B-spline over the keyframes, indices clamped at the ends. Its quaternion is normalised.
NgpKeyframe evalNgpPath(std::span<const NgpKeyframe> keys, double t);

// The keyframe's camera-to-world in the dataset's frame, row-major, OpenGL convention: instant-ngp's
// ngp_matrix_to_nerf applied to the keyframe's matrix.
std::array<double, 16> ngpPoseToDataset(const NgpKeyframe& k, const NgpFrame& frame);

// The scale and offset instant-ngp took from `scene` (see CameraPathOptions::scene).
NgpFrame ngpFrameOfScene(const std::string& scene);

CameraPath readNgpCameraPath(const JsonFile& f, const CameraPathOptions& options);

}  // namespace vknerf::io::detail

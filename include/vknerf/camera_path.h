#pragma once
// A camera path to render, in the dataset's world frame, read from either of two formats (told
// apart by content: a top-level "camera_path" or "path"):
//
// nerfstudio's camera path JSON (what its viewer's "Render" panel exports and ns-render reads):
//   { "render_width": W, "render_height": H, "fps": F, "seconds": S (optional),
//     "camera_type": "perspective" (optional; the only type read),
//     "camera_path": [ { "camera_to_world": [16 numbers, row-major 4x4, OpenGL convention],
//                        "fov": vertical field of view in degrees }, ... ] }
//   One camera per entry of camera_path: nerfstudio writes the interpolated frames, fps * seconds of
//   them, at the file's size. CameraPathOptions' size and duration do not apply.
//
// instant-ngp's base_cam.json (what its GUI's camera path editor saves and scripts/run.py's
// --video_camera_path reads):
//   { "path": [ { "R": [x, y, z, w] unit quaternion, "T": [x, y, z], "fov": vertical, degrees,
//                 "slice", "scale", "aperture_size" (or "dof"): read by instant-ngp's viewer, ignored here },
//               ... ],
//     "time": the GUI's play position (ignored) }
//   Keyframes, not frames: as run.py renders them, frame i of n = fps * seconds is the uniform cubic
//   B-spline through the keyframes at t = i / n (keyframe indices clamped at the ends, t scaled by
//   keyframes - 1; quaternions blended linearly with their signs aligned, then normalised; T and fov
//   blended alike). The poses are camera-to-world in instant-ngp's internal frame (x right, y down,
//   z forward, its axes cycled from the dataset's and the dataset scaled by `scale` and moved by
//   `offset`); they are brought back to the dataset's frame with the scene's scale and offset, as
//   instant-ngp's ngp_matrix_to_nerf does. instant-ngp renders with motion blur over half a frame;
//   here each frame is the pose at the start of its interval. The newer timed format (keyframes
//   with "timestamp", "loop") is refused.
#include <string>
#include <vector>

#include "vknerf/camera.h"

namespace vknerf {

// What an instant-ngp path leaves to the renderer; the defaults are run.py's.
struct CameraPathOptions {
  uint32_t width = 1920, height = 1080;  // --width, --height
  double fps = 60;                       // --video_fps
  double seconds = 1;                    // --video_n_seconds
  // The scene the path was made on: its transforms.json (or the folder holding transforms.json or
  // transforms_train.json), for instant-ngp's "scale", "offset" and "aabb". Empty, or a scene
  // without one (a COLMAP folder): instant-ngp's defaults, scale 0.33 and offset (0.5, 0.5, 0.5).
  std::string scene;
};

struct CameraPath {
  enum class Format { nerfstudio, instantNgp };
  Format format = Format::nerfstudio;
  std::vector<Camera> cameras;  // pinhole, principal point at the image centre
  double fps = 24;
  // instant-ngp: the scale and offset used and where they came from, one line for the user.
  std::string frameNote;
};

// Throws vknerf::Error naming the file and the field for anything missing, malformed, not finite as
// a float, or out of range (sizes 1..16384, fov in (0, 180), fps in (0, 1000], a rigid pose, a unit
// quaternion within 1e-3, at least one keyframe).
CameraPath loadCameraPath(const std::string& path, const CameraPathOptions& options = {});

}  // namespace vknerf

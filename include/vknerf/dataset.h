#pragma once
// Posed photos in: nerf_synthetic / instant-ngp / nerfstudio `transforms*.json`, or a COLMAP text model.
// Every loader produces cameras in the OpenGL convention of vknerf/camera.h (camera-to-world, the
// camera looks down -Z, +Y up) and one RGBA8 image per camera, all of one size.
//
// `path` is one of
//   - a folder holding transforms_{train,val,test}.json (split files) or transforms.json (one file);
//   - a path to one JSON file. A file named transforms_<split>.json is a split on its own: all its
//     frames are loaded and options.split is ignored. Any other JSON file is split by the holdout;
//   - a COLMAP text model: the scene folder holding sparse/0/ or sparse/, or the folder holding
//     cameras.txt itself; images come from the nearest images/ folder at or above the model.
// Splits: options.split is "train", "val", "test" or "all". Split files are used when present;
// otherwise a deterministic holdout sends round(holdoutFraction * n) (at least one when the fraction is
// positive) evenly spaced frames to "val" and "test" (the same frames) and the rest to "train".
//
// Poses and scene box:
//   - JSON: poses are kept in the file's world frame. The box comes from, in order: "aabb"
//     [[min xyz], [max xyz]] in that frame ("json aabb"); instant-ngp's "aabb_scale" / "scale" /
//     "offset" (ngp maps p -> p * scale + offset into a cube of side aabb_scale centred at 0.5;
//     defaults 0.33, 0.5, 1), mapped back into the file's frame ("aabb_scale"); else derived from
//     the cameras ("cameras", or "cameras+alpha" when alpha masks carved it down).
//   - COLMAP: world-to-camera (OpenCV: x right, y down, z forward) becomes camera-to-world in the
//     OpenGL convention by negating the camera's y and z axes. The scene is then translated and
//     uniformly scaled (never rotated) so that the box, from the 1st-99th percentiles of points3D.txt
//     ("points3D") or else from the cameras ("cameras"), is centred at the origin with its largest
//     half extent 1.
// A camera-derived box is centred at the least-squares point closest to all optical axes, with half
// extent the median over cameras of distance * tan(half field of view).
#include <cstdint>
#include <string>
#include <vector>

#include "vknerf/camera.h"

namespace vknerf {

// Straight (not premultiplied) alpha, sRGB-encoded values, rows top to bottom.
struct ImageRGBA8 {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

struct DatasetOptions {
  std::string split = "train";   // "train", "val", "test" or "all"
  uint32_t downscale = 1;        // box-filter the images by this factor (intrinsics follow)
  float holdoutFraction = 0.1f;  // share of frames held out when there are no split files, in [0, 1)
};

struct Dataset {
  std::vector<Camera> cameras;     // OpenGL convention, c2w row-major
  std::vector<ImageRGBA8> images;  // same order as cameras; all the same size
  std::vector<std::string> names;  // image file paths (for reports)
  Aabb bounds;                     // scene box, in the frame of `cameras`
  std::string boundsSource;        // "json aabb", "aabb_scale", "cameras", "cameras+alpha", "points3D"

  static Dataset load(const std::string& path, const DatasetOptions& options = {});  // throws vknerf::Error
};

}  // namespace vknerf

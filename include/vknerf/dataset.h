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
//     cameras.txt itself; images come from the first images/ folder found in the model folder or
//     the two folders above it (e.g. <scene>/images/ for <scene>/sparse/0/).
// Splits: options.split is "train", "val", "test" or "all". Split files are used when present;
// otherwise a deterministic holdout sends round(holdoutFraction * n) (at least one when the fraction is
// positive) evenly spaced frames to "val" and "test" (the same frames) and the rest to "train".
//
// Poses and scene box:
//   - JSON: poses are kept in the file's world frame. The box comes from, in order: "aabb"
//     [[min xyz], [max xyz]] in that frame ("json aabb"); instant-ngp's "aabb_scale" / "scale" /
//     "offset": ngp maps p -> p * scale + offset (defaults 0.33, 0.5) and keeps the cube of side
//     aabb_scale (default 1, at most 128) centred at 0.5, which maps back to the box
//     ((0.5 -+ aabb_scale / 2) - offset) / scale ("aabb_scale", with Dataset::aabbScale); else the
//     cameras (below).
//   - COLMAP: world-to-camera (OpenCV: x right, y down, z forward) becomes camera-to-world in the
//     OpenGL convention by negating the camera's y and z axes. The scene is then translated and
//     uniformly scaled (never rotated) so that its box, the 1st-99th percentiles of points3D.txt per
//     axis padded by 5% ("points3D") or else the camera box ("cameras"), is centred at the origin
//     with its largest half extent 1.
//   - From the cameras (of every split, so the splits agree): centred at the least-squares point
//     closest to all optical axes, half extent the median over cameras of distance * tan(half the
//     wider field of view) ("cameras"); then, when the loaded images have transparent pixels,
//     shrunk to the visual hull of their alpha masks ("cameras+alpha").
// Unsupported: lens distortion (nonzero k1..k4, p1, p2 or COLMAP distortion parameters) and
// non-pinhole camera models are errors; undistort the images first.
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
  // instant-ngp's aabb_scale ("aabb_scale" bounds): the box's side over that of the inner cube the
  // cameras look into; 1 otherwise. The fast model nests 1 + ceil(log2(aabbScale)) occupancy cascades.
  float aabbScale = 1;

  static Dataset load(const std::string& path, const DatasetOptions& options = {});  // throws vknerf::Error
};

}  // namespace vknerf

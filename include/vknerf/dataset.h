#pragma once
// Posed photos in: nerf_synthetic / instant-ngp / nerfstudio `transforms*.json`, a COLMAP model
// (text or binary), or LLFF's `poses_bounds.npy`.
// Every loader produces cameras in the OpenGL convention of vknerf/camera.h (camera-to-world, the
// camera looks down -Z, +Y up) and one RGBA8 image per camera; images may differ in size (nerfstudio's
// per-frame `w`/`h`).
//
// `path` is one of
//   - a folder holding transforms_{train,val,test}.json (split files) or transforms.json (one file);
//   - a path to one JSON file. A file named transforms_<split>.json is a split on its own: all its
//     frames are loaded and options.split is ignored. Any other JSON file is split by the holdout;
//   - a COLMAP model: the scene folder holding sparse/0/ or sparse/, or the model folder itself;
//     images come from the first images/ folder found in the model folder or the two folders above
//     it (e.g. <scene>/images/ for <scene>/sparse/0/). The model is read as text (cameras.txt,
//     images.txt, points3D.txt) when cameras.txt or images.txt is there, else as binary
//     (cameras.bin, images.bin, points3D.bin, COLMAP's default output); a folder holding both forms
//     is read as text, the form a person edits (points3D is then points3D.txt). Both forms load
//     to the same Dataset.
//   - LLFF: a folder holding poses_bounds.npy (read before a COLMAP model beside it, as LLFF's
//     scenes ship both; name sparse/0/ to read the model), or the .npy file itself. The .npy holds
//     N rows of 17 float64 or float32 values (numpy format 1.0 or 2.0, little-endian): a 3x5
//     matrix row by row, [R | t | hwf] with R's columns the camera's down, right and back axes in
//     the world, t its position and hwf the height, width and focal length in pixels of the photos
//     in images/; then the near and far depth bounds. The photos are the .png/.jpg/.jpeg files of
//     images/ sorted by name, one per row. With options.downscale N > 1 and an images_N/ folder
//     beside images/, the photos come from images_N/ as they are (not resampled): the focal length
//     scales by each photo's width over W (and height over H for fy), the principal point is the
//     photo's centre. Without images_N/, images/ is box-filtered as for every format.
// Splits: options.split is "train", "val", "test" or "all". Split files are used when present;
// LLFF holds out every 8th photo (index i % 8 == 0, "llffhold 8" as the NeRF papers evaluate) for
// "val" and "test" (the same photos) and ignores holdoutFraction; otherwise a deterministic holdout
// sends round(holdoutFraction * n) (at least one when the fraction is positive) evenly spaced
// frames to "val" and "test" (the same frames) and the rest to "train".
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
//     uniformly scaled (never rotated) so that its box, the 1st-99th percentiles of points3D per
//     axis padded by 5% ("points3D") or else the camera box ("cameras"), is centred at the origin
//     with its largest half extent 1. With points, that box is the inner cube of cascades: the scene
//     box is it scaled by aabbScale, the power of two (at most 16) that holds 99.9% of the points
//     (the walls and far background a capture sees sparsely).
//   - LLFF: [right, up, back] = [R's column 1, -R's column 0, R's column 2] (NeRF's load_llff), in the
//     file's world frame, neither recentred nor rescaled (the same cameras as transforms.json give
//     the same rays). The box is nested cascades (aabbScale) about an inner cube on the cameras'
//     mean axis at 1.5 times the median near bound, wide enough for every frame there, doubled until
//     it holds every camera's frustum between its near and far bound, over all photos of every split
//     ("llff bounds"); the bounds are kept in Dataset::depthBounds.
//   - From the cameras (of every split, so the splits agree): centred at the least-squares point
//     closest to all optical axes, half extent the median over cameras of distance * tan(half the
//     wider field of view) ("cameras"); then, when the loaded images have transparent pixels,
//     shrunk to the visual hull of their alpha masks ("cameras+alpha").
// Lenses (Camera::lens, applied where rays are generated; the photos are never resampled):
//   - JSON, at the top level or per frame: nerfstudio's camera_model PINHOLE, OPENCV (k1 k2 k3
//     radial, p1 p2 tangential) or OPENCV_FISHEYE (k1..k4); without camera_model, instant-ngp's
//     keys: is_fisheye true reads k1..k4 as the fisheye's, otherwise nonzero k1 k2 k3 p1 p2 make an
//     OpenCV lens (k3 as OpenCV's r^6 term) and a nonzero k4 is an error. Any other camera_model is
//     an error naming the field.
//   - COLMAP: SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV, FULL_OPENCV (LensModel::OpenCV),
//     OPENCV_FISHEYE, SIMPLE_RADIAL_FISHEYE, RADIAL_FISHEYE (LensModel::Fisheye); FOV and
//     THIN_PRISM_FISHEYE are errors naming the file and record.
//   - Every lens must invert over its whole image (checkLens in vknerf/camera.h), else loading fails
//     naming the file, the coefficients and the pixel where it fails. Downscaling keeps the
//     (dimensionless) coefficients and scales the focal lengths and principal point.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
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
  uint32_t downscale = 1;        // box-filter the images by this factor (intrinsics follow); LLFF: images_N/ if any
  float holdoutFraction = 0.1f;  // share of frames held out when there are no split files, in [0, 1)
  uint32_t threads = 0;          // images decoded at once; 0: one per core
  // Called after each image is decoded with (images done, images in all), from the decoding
  // threads but never two calls at once.
  std::function<void(size_t done, size_t total)> progress;
};

struct Dataset {
  std::vector<Camera> cameras;     // OpenGL convention, c2w row-major
  std::vector<ImageRGBA8> images;  // same order as cameras, each of its camera's size
  std::vector<std::string> names;  // image file paths (for reports)
  Aabb bounds;                     // scene box, in the frame of `cameras`
  std::string boundsSource;        // "json aabb", "aabb_scale", "cameras", "cameras+alpha", "points3D", "llff bounds", "given"
  // instant-ngp's aabb_scale ("aabb_scale" bounds): the box's side over that of the inner cube the
  // cameras look into; 1 otherwise. The fast model nests 1 + ceil(log2(aabbScale)) occupancy cascades.
  float aabbScale = 1;
  // Per camera (same order as `cameras`) when the format states them (LLFF), else empty: {near,
  // far}, 0 < near < far, the depths between which the camera sees the scene, measured along its
  // optical axis (-Z of its c2w) in the units of `cameras`; a ray with unit direction d in the
  // camera's frame reaches depth z at distance z / -d.z.
  std::vector<std::array<float, 2>> depthBounds;

  static Dataset load(const std::string& path, const DatasetOptions& options = {});  // throws vknerf::Error
  // A dataset from cameras and images already in memory (an embedding application's, the Python
  // module's), checked as a loaded one is: one image per camera, each its camera's size, finite
  // positive intrinsics, every lens inverting over its image (checkLens). The box is `bounds` when
  // given ("given"), else placed from the cameras as for a scene file without one ("cameras" or
  // "cameras+alpha"). `names` (optional: one per camera) name the images in reports.
  static Dataset fromMemory(std::vector<Camera> cameras, std::vector<ImageRGBA8> images,
                            std::vector<std::string> names = {}, std::optional<Aabb> bounds = std::nullopt);
};

}  // namespace vknerf

#pragma once
// Shared by the dataset loaders: a format reader turns its files into FrameSpecs (pose + whatever
// intrinsics the file states); Dataset::load (src/api/dataset.cpp) reads the scene through
// readScene(), loads the images, fills in the rest of the intrinsics, downscales and finds the scene
// box with the functions below.
#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "vknerf/dataset.h"

namespace vknerf::io::detail {

namespace fs = std::filesystem;

// NaN / 0 where the file does not say; completed from the image size by completeCamera().
struct Intrinsics {
  double fx = NAN, fy = NAN, cx = NAN, cy = NAN;
  double angleX = NAN, angleY = NAN;  // full field of view, radians
  uint32_t width = 0, height = 0;
  // Nonzero when fx, fy, cx, cy are stated for an image of this size and the image may be a resized
  // copy of it (LLFF's images_N/): they scale by the image's size over this one, axis by axis.
  uint32_t statedWidth = 0, statedHeight = 0;
  // Nonzero when the image is meant to be this many times smaller than the stated size (images_N/'s
  // N): its size must be the stated one over it, to within a pixel's rounding. The fields that state
  // the size, for that message.
  uint32_t statedFactor = 0;
  std::string statedWidthField = "width", statedHeightField = "height";
  Lens lens;  // distortion coefficients are dimensionless: downscaling leaves them alone
  // The fields the focal lengths come from, for messages: transforms.json's unless the format says.
  std::string focalFieldX = "fl_x or camera_angle_x", focalFieldY = "fl_y or camera_angle_y";
};

struct FrameSpec {
  std::string where;  // names the frame in messages: "transforms_train.json: frames[3]", "images.txt:12"
  fs::path image;     // resolved image file; empty when none was found
  std::string imageTried;  // the paths tried, for the error when `image` is empty
  Intrinsics intrinsics;
  std::array<double, 16> c2w{};  // OpenGL convention, row-major, already checked to be rigid
  std::string poseField = "transform_matrix";  // where the pose comes from, for messages
  std::optional<std::array<float, 2>> depthBounds;  // near, far along the optical axis, when the file states them
};

struct SceneSpec {
  std::vector<FrameSpec> frames;  // the requested split, in order
  std::vector<FrameSpec> others;  // every other frame of the scene: used for the scene box only
  bool hasBox = false;            // the files state the box
  Aabb box;
  std::string boxSource;
  float aabbScale = 1;            // instant-ngp's aabb_scale, when the files give one
  // The factor Dataset::load shrinks the images by, when the reader found them already smaller than
  // the size the intrinsics are stated for (LLFF's images_N/); options.downscale otherwise.
  std::optional<uint32_t> downscale;
};

// The scene at `path` (what Dataset::load was given), read by the reader its files call for:
// transforms files, then poses_bounds.npy, then a COLMAP model in sparse/0/, sparse/ or the folder
// itself, its images/ in the model's folder, one of the two above it, or `path`. Throws when there is
// none.
SceneSpec readScene(const fs::path& path, const DatasetOptions& options);
// An image listed twice with two poses (a copied frame whose file_path was not changed) would train
// on both, each pulling the field its own way: an error naming both entries. The same pose twice is
// only repetition, and is let through. Every split counts: the scene is one set of photos.
void checkOnePosePerImage(const SceneSpec& scene);

// Readers. `target` is what Dataset::load was given, already classified.
SceneSpec readTransformsJson(const fs::path& target, const DatasetOptions& options);
// A COLMAP model folder is text when it holds cameras.txt or images.txt (the form vknerf read
// first, and the one a person edits), else binary when it holds cameras.bin or images.bin.
enum class ColmapForm { none, text, binary };
ColmapForm colmapForm(const fs::path& modelDir);
// Reads the model in `modelDir` in the form colmapForm() names.
SceneSpec readColmap(const fs::path& modelDir, const fs::path& imagesDir, const DatasetOptions& options);

// LLFF's poses_bounds.npy (`file`), its photos in images/ or images_N/ beside it (llff_photos.h says
// which is used when).
SceneSpec readLlff(const fs::path& file, const DatasetOptions& options);

// Indices of frames in `split` ("train", "val", "test", "all") of n frames, holding out
// round(fraction * n) evenly spaced frames (at least one when fraction > 0) for val/test.
std::vector<size_t> holdoutIndices(size_t n, float fraction, const std::string& split);

// Throws unless the 3x3 part of `m` is a rotation (orthonormal, det +1, within 1e-3) and its
// translation is finite and its last row (0, 0, 0, 1).
void checkRigid(const std::array<double, 16>& m, const std::string& where, const char* field = "transform_matrix");

// Intrinsics for an image of width x height: focal lengths from fl_* or camera_angle_*, principal
// point defaulting to the image centre, the lens as the file states it. Throws (naming `f.where`)
// when the file's size disagrees with the image's, the focal length is missing or not positive, or
// the lens does not invert over the image (checkLens, vknerf/camera.h).
Camera completeCamera(const FrameSpec& f, uint32_t width, uint32_t height);
// The camera of `fullRes`'s image downscaled by `downscale` to width x height.
Camera downscaledCamera(const Camera& fullRes, uint32_t downscale, uint32_t width, uint32_t height);

// Loads (and box-filters by `downscale`) every frame's image, options.threads (default: every core)
// at a time; rethrows the first failure in frame order so the message does not depend on thread
// timing.
std::vector<ImageRGBA8> loadImages(const std::vector<FrameSpec>& frames, uint32_t downscale, const DatasetOptions& options);

// The device computes in 32-bit floats, and ray arithmetic squares positions and multiplies pixel
// offsets by 1/f: a value that is finite as a double can be infinite there. kDeviceLimit leaves
// room for those products (1e15 squared is 1e30, below float's 3.4e38).
constexpr double kDeviceLimit = 1e15;

// The box holding every camera's view frustum between its near and far depth (along the optical
// axis, depthBounds[i] = {near, far}): the bounds of the frustums' corners, where the rays through
// the image corners reach those depths. Pinhole cameras only (a lens would bend the frustum's
// edges); throws otherwise, or when the spans' sizes differ or are zero.
Aabb boxFromFrustums(std::span<const Camera> cameras, std::span<const std::array<float, 2>> depthBounds);

// A forward-facing capture's box as nested cascades (instant-ngp's aabb_scale) from the same depth
// bounds: the inner cube sits on the cameras' mean optical axis at 1.5 times the median near depth,
// wide enough for every camera's frame there (and at least half that depth on each side), where the
// nearest content lies and pixels are finest; the box is that cube doubled until it holds every
// frustum out to its far bound (`frustums`, boxFromFrustums of the same), at most 128 times. Returns
// the box, with its side over the inner cube's in `aabbScale`.
Aabb cascadedBoxFromDepths(std::span<const Camera> cameras, std::span<const std::array<float, 2>> depthBounds,
                           const Aabb& frustums, float& aabbScale);

// Scene box from the cameras alone (see vknerf/dataset.h); needs at least one camera.
Aabb boxFromCameras(std::span<const Camera> cameras);
// Shrinks `box` to the bounds of the visual hull of the alpha masks (pixels with alpha > 0), found
// on a 64^3 grid over `box`: a cell stays unless some camera with its centre in view sees all of it
// (as much as lies in the frame) on transparent pixels, and counts only if some camera has its
// centre in view. Conservative for objects fully in view: every cell holding an opaque point is
// kept. Returns false, leaving `box` alone, when no image has a fully transparent pixel, some camera
// has lens distortion (the carving projects through the pinhole model) or the masks leave nothing.
bool carveWithAlpha(std::span<const Camera> cameras, std::span<const ImageRGBA8> images, Aabb& box);

}  // namespace vknerf::io::detail

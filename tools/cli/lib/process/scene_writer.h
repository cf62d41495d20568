#pragma once
// Writing SCENE: it is built in a staging folder beside it and renamed into place only when whole,
// so a failed run never leaves a half-written folder that looks like a scene, and an existing
// SCENE is replaced only by a complete one. Layout (what `vknerf train SCENE` reads):
//   SCENE/images/           the photos or video frames COLMAP saw
//   SCENE/images_N/         with --downscale N: copies N times smaller, PNG
//   SCENE/sparse/0/         the largest COLMAP model (binary, as COLMAP wrote it)
//   SCENE/transforms.json   the same cameras (lens included) and box for tools that read instant-ngp's
//                           format; `vknerf train SCENE` reads this one when both are there
//   SCENE/colmap/           COLMAP's database and every model the mapper made
//   SCENE/colmap.log        the output of colmap (and ffmpeg)
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "vknerf/camera.h"

namespace vknerf::process {

// "<parent>/.<name>.partial-<pid>": hidden, beside `target` so the final rename stays on one file
// system.
std::filesystem::path stagingFolder(const std::filesystem::path& target);

struct SceneBox {
  Aabb box;
  std::string source;  // how vknerf chose it: "points3D" (percentiles of the points) or "cameras"
};

// Reads the COLMAP model in scene/sparse/0 the way `vknerf train` does and writes
// scene/transforms.json with the same cameras and box (and scene/images_N/ for downscale N > 1, the
// JSON then naming those with intrinsics divided by N, exactly as `vknerf train SCENE/sparse/0
// --downscale N` would). Returns the box. Throws vknerf::Error. `progress`, when given, counts the
// images decoded and then (downscale N > 1) the copies written: (done, total).
SceneBox writeTransforms(const std::filesystem::path& scene, uint32_t downscale,
                         const std::function<void(size_t done, size_t total)>& progress = {});

// Throws vknerf::Error unless `target` is absent, an empty folder or a scene vknerf process wrote
// (colmap.log and sparse/ in it): publishScene removes what it replaces, and anything else there
// is someone's data.
void checkReplaceable(const std::filesystem::path& target);

// Renames `staging` to `target`; an existing target is moved aside first and removed only once the
// new scene is in place. Throws vknerf::Error naming both.
void publishScene(const std::filesystem::path& staging, const std::filesystem::path& target);

}  // namespace vknerf::process

#pragma once
// The files a scene is made of, as each format the loader reads declares them, so that the one
// place that checks a command's outputs (tools/cli/command_files.h) can refuse to write over one,
// whether or not the command was given the scene: `export cameras -o scene/transforms_train.json`
// would otherwise replace the scene it names.
//
//   transforms: transforms.json, transforms_<split>.json, and every PNG or JPEG under the folder
//               (a frame's file_path may name any of them);
//   COLMAP:     cameras, images and points3D (.txt or .bin) in the folder, sparse/ and sparse/<n>/,
//               and the photos in images/;
//   LLFF:       poses_bounds.npy and the photos in images/ and images_<n>/;
//   any:        a file named images, images_<n> or sparse in the folder (it would stand where the
//               loader looks for the photos or the model).
#include <filesystem>
#include <optional>
#include <string>

namespace vknerf {

// True when `folder` is the folder of a scene the loader would read (Dataset::load): it holds a
// transforms file, poses_bounds.npy or a COLMAP model, in itself or in sparse/ or sparse/0/.
bool isSceneFolder(const std::filesystem::path& folder);

// True when `file` (which need not exist) is one of the files the scene in `folder` declares, or
// would become one if written (a new transforms_val.json adds a split; a new photo in images/
// changes LLFF's photo count). A PNG or JPEG elsewhere under the folder is one only if it exists.
bool declaresSceneFile(const std::filesystem::path& folder, const std::filesystem::path& file);

// The scene whose file `file` is: its own folder, or the one or two above it (COLMAP's sparse/0/,
// images/), when that is a scene folder declaring it; none otherwise.
std::optional<std::filesystem::path> sceneDeclaring(const std::filesystem::path& file);

// The scene whose photo or model folder (images/, images_<n>/, sparse/) `folder` is or lies in: a
// folder output there (`render -o scene/images`) would add files the loader reads as the scene's.
std::optional<std::filesystem::path> sceneHoldingFolder(const std::filesystem::path& folder);

}  // namespace vknerf

// Which reader reads a dataset path: transforms files, then poses_bounds.npy, then a COLMAP model;
// and the check of the scene they read that no image has two poses.
#include <algorithm>
#include <cmath>
#include <map>

#include "io/dataset/dataset_loaders.h"
#include "vknerf/error.h"

namespace vknerf::io::detail {
namespace {

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}
bool isDir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

}  // namespace

SceneSpec readScene(const fs::path& path, const DatasetOptions& options) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("dataset '" + path.string() + "' does not exist");
  // A pipe or a device (a FIFO named poses_bounds.npy) is neither a scene file nor a folder: say so,
  // rather than look into it for a scene's files as into a folder.
  if (!isFile(path) && !isDir(path))
    throw Error("dataset '" + path.string() + "' is neither a file nor a folder (a pipe or a device): give the scene "
                "folder, a transforms JSON or poses_bounds.npy");
  if (isFile(path)) {
    if (path.extension() == ".json") return readTransformsJson(path, options);
    if (path.extension() == ".npy") return readLlff(path, options);
    throw Error("dataset '" + path.string() + "' is a file but not a .json transforms file or LLFF's poses_bounds.npy");
  }
  if (isFile(path / "transforms_train.json") || isFile(path / "transforms.json"))
    return readTransformsJson(path, options);
  // LLFF's scenes ship a COLMAP model beside poses_bounds.npy; the .npy, with its bounds, its
  // images_N/ and the papers' test split, is what they are evaluated with.
  if (isFile(path / "poses_bounds.npy")) return readLlff(path / "poses_bounds.npy", options);
  for (const fs::path& model : {path / "sparse" / "0", path / "sparse", path}) {
    if (colmapForm(model) == ColmapForm::none) continue;
    // The scene folder holds images/; the model sits in it, or in its sparse/ or sparse/0/.
    for (const fs::path& scene : {model, model.parent_path(), model.parent_path().parent_path(), path})
      if (isDir(scene / "images")) return readColmap(model, scene / "images", options);
    throw Error("COLMAP model '" + model.string() + "': no images/ folder in it or the two folders above it");
  }
  throw Error("dataset '" + path.string() +
              "': no transforms_train.json, transforms.json, poses_bounds.npy or COLMAP model (sparse/0/cameras.txt or cameras.bin) in it");
}

void checkOnePosePerImage(const SceneSpec& scene) {
  std::map<fs::path, const FrameSpec*> first;
  for (const auto* list : {&scene.frames, &scene.others})
    for (const FrameSpec& f : *list) {
      if (f.image.empty()) continue;
      std::error_code ec;
      fs::path key = fs::weakly_canonical(f.image, ec);
      if (ec) key = f.image;
      const auto [at, added] = first.emplace(key, &f);
      if (added) continue;
      double scale = 1, gap = 0;
      for (int i = 0; i < 16; ++i) {
        scale = std::max({scale, std::fabs(f.c2w[i]), std::fabs(at->second->c2w[i])});
        gap = std::max(gap, std::fabs(f.c2w[i] - at->second->c2w[i]));
      }
      if (gap > 1e-6 * scale)
        throw Error(f.where + ": image '" + f.image.string() + "' is listed again with another pose than at " +
                    at->second->where + "; one photo has one pose");
    }
}

}  // namespace vknerf::io::detail

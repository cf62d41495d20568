// What each scene format declares as its files (vknerf/scene_files.h). The names follow the loaders:
// readScene (src/io/dataset/read_scene.cpp) picks transforms files, then poses_bounds.npy, then a
// COLMAP model in the folder, sparse/0/ or sparse/; COLMAP and LLFF read their photos from images/
// (LLFF's downscaled copies from images_<n>/).
#include "vknerf/scene_files.h"

#include <algorithm>
#include <cctype>

namespace vknerf {
namespace {

namespace fs = std::filesystem;

bool present(const fs::path& p) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(p, ec));
}

bool isFolder(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool isPoses(const std::string& name) {
  const std::string n = lower(name);
  return n.size() >= 15 && n.rfind("transforms", 0) == 0 && n.substr(n.size() - 5) == ".json";
}

bool isColmapModelFile(const std::string& name) {
  for (const char* stem : {"cameras", "images", "points3D"})
    for (const char* ext : {".txt", ".bin"})
      if (name == std::string(stem) + ext) return true;
  return false;
}

bool isPhoto(const std::string& name) {
  const std::string ext = lower(fs::path(name).extension().string());
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}

// images/ or images_<n>/ (n a whole number), LLFF's and COLMAP's photo folders.
bool isPhotoFolderName(const std::string& name) {
  if (name == "images") return true;
  if (name.rfind("images_", 0) != 0 || name.size() == 7) return false;
  return std::all_of(name.begin() + 7, name.end(), [](unsigned char c) { return std::isdigit(c); });
}

bool holdsColmapModel(const fs::path& dir) {
  for (const char* name : {"cameras.txt", "images.txt", "cameras.bin", "images.bin"})
    if (present(dir / name)) return true;
  return false;
}

// Absolute, without "." or "..", its folder's symlinks resolved (the file itself need not exist,
// and a symlink at the end is kept: the writer renames over the link, not into what it names).
fs::path normal(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec).lexically_normal();
  if (!a.has_filename() && a.has_relative_path()) a = a.parent_path();
  fs::path folder = fs::weakly_canonical(a.parent_path(), ec);
  return ec ? a : folder / a.filename();
}

// A folder, every symlink on its path resolved, so that it compares with normal()'s folders.
fs::path normalFolder(const fs::path& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec).lexically_normal();
  if (!a.has_filename() && a.has_relative_path()) a = a.parent_path();
  fs::path c = fs::weakly_canonical(a, ec);
  return ec ? a : c;
}

}  // namespace

bool isSceneFolder(const fs::path& folder) {
  if (!isFolder(folder)) return false;
  if (present(folder / "transforms.json") || present(folder / "transforms_train.json") ||
      present(folder / "poses_bounds.npy"))
    return true;
  return holdsColmapModel(folder) || holdsColmapModel(folder / "sparse") || holdsColmapModel(folder / "sparse" / "0");
}

bool declaresSceneFile(const fs::path& sceneFolder, const fs::path& file) {
  const fs::path scene = normalFolder(sceneFolder), f = normal(file);
  const std::string name = f.filename().string();
  // The path of the file's folder below the scene's: "" for the scene folder itself.
  const fs::path below = f.parent_path().lexically_relative(scene);
  if (below.empty() || *below.begin() == "..") return false;
  const bool atTop = below == ".";
  if (atTop && (isPoses(name) || name == "poses_bounds.npy")) return true;
  // A file named as the scene's photo or model folders would stand where the loader looks for them.
  if (atTop && (isPhotoFolderName(name) || name == "sparse")) return true;
  if (isColmapModelFile(name)) {
    if (atTop) return true;
    auto it = below.begin();
    if (*it == "sparse" && (++it == below.end() || std::next(it) == below.end())) return true;
  }
  if (!isPhoto(name)) return false;
  if (!atTop && isPhotoFolderName(below.begin()->string())) return true;
  return present(f);
}

std::optional<fs::path> sceneHoldingFolder(const fs::path& folder) {
  const fs::path f = normalFolder(folder);
  fs::path scene = f.parent_path();
  for (int up = 0; up < 3 && scene != scene.parent_path(); ++up, scene = scene.parent_path()) {
    const std::string first = f.lexically_relative(scene).begin()->string();
    if ((isPhotoFolderName(first) || first == "sparse") && isSceneFolder(scene)) return scene;
  }
  return std::nullopt;
}

std::optional<fs::path> sceneDeclaring(const fs::path& file) {
  fs::path folder = normal(file).parent_path();
  for (int up = 0; up < 3; ++up, folder = folder.parent_path()) {
    if (isSceneFolder(folder) && declaresSceneFile(folder, file)) return folder;
    if (folder == folder.parent_path()) break;
  }
  return std::nullopt;
}

}  // namespace vknerf

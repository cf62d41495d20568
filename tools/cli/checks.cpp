#include "checks.h"

#include <cctype>
#include <cmath>
#include <filesystem>

#include "vknerf/file_output.h"

namespace vknerf::cli {
namespace {

namespace fs = std::filesystem;

CLI::Validator numberCheck(const char* name, bool positive) {
  return CLI::Validator(
      [positive](std::string& s) -> std::string {
        double v = 0;
        size_t used = 0;
        try {
          v = std::stod(s, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != s.size() || !std::isfinite(v) || (positive && !(v > 0)))
          return std::string("must be a ") + (positive ? "positive " : "") + "finite number, got " + s;
        return "";
      },
      name);
}

// The folder a scene argument names (the scene folder, or the folder of a transforms JSON / COLMAP file).
fs::path sceneFolder(const std::string& scene) {
  std::error_code ec;
  fs::path p = fs::absolute(scene, ec);
  return fs::is_directory(p, ec) ? p : p.parent_path();
}

}  // namespace

const CLI::Validator PositiveFinite = numberCheck("POSITIVE", true);
const CLI::Validator FiniteNumber = numberCheck("FINITE", false);

void checkOutput(const std::string& path, const std::string& what, const std::string& scene) {
  checkOutputPath(path, what);
  if (scene.empty()) return;
  // A scene's own files: what the scene argument names, and the poses (transforms*.json), COLMAP
  // model and images under the scene folder. Other names there (a model, a report) are fine.
  std::error_code ec;
  if (!fs::exists(path, ec)) return;
  const fs::path out = fs::weakly_canonical(path, ec), folder = fs::weakly_canonical(sceneFolder(scene), ec);
  const bool isScene = fs::equivalent(path, scene, ec);
  const auto rel = out.lexically_relative(folder);
  const bool inside = !rel.empty() && *rel.begin() != "..";
  std::string ext = out.extension().string(), stem = out.stem().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  const bool poses = ext == ".json" && stem.rfind("transforms", 0) == 0;
  const bool colmap = (ext == ".txt" || ext == ".bin") && (stem == "cameras" || stem == "images" || stem == "points3D");
  const bool image = ext == ".png" || ext == ".jpg" || ext == ".jpeg";
  const bool sceneKind = poses || colmap || image;
  if (isScene || (inside && sceneKind))
    throw Error(what + " " + path + ": is one of the scene's own files (" + scene + "); choose another output");
}

}  // namespace vknerf::cli

#include "lib/camera_frames.h"

#include <filesystem>

#include "vknerf/error.h"
#include "vknerf/image_io.h"

namespace vknerf::nerf {
namespace {

namespace fs = std::filesystem;

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// Both sides through the file system (symlinks resolved), since the loader's ".." steps out of the
// folder the JSON physically lies in.
std::string relativeTo(const fs::path& file, const fs::path& folder) {
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(fs::absolute(file), ec), b = fs::weakly_canonical(fs::absolute(folder), ec);
  if (ec) return file.string();
  const fs::path rel = a.lexically_relative(b);
  if (rel.empty()) return a.string();
  // Sharing nothing but the root, the absolute path says it plainly.
  size_t up = 0, depth = 0;
  for (const fs::path& part : rel) up += part == "..";
  for (const fs::path& part : b.relative_path()) depth += !part.empty();
  return up >= depth ? a.string() : rel.string();
}

// The downscale factor k >= 1 that turns a width x height image into the camera's size, or 0.
uint32_t downscaleOf(uint32_t width, uint32_t height, const Camera& c) {
  for (uint32_t k = 1; c.width && k <= width / c.width; ++k)
    if (width / k == c.width && height / k == c.height) return k;
  return 0;
}

}  // namespace

std::vector<TrainedCamera> framesForFile(const std::vector<TrainedCamera>& cameras, const std::string& output) {
  const fs::path folder = fs::path(output).parent_path().empty() ? fs::path(".") : fs::path(output).parent_path();
  std::vector<TrainedCamera> frames = cameras;
  for (size_t i = 0; i < frames.size(); ++i) {
    TrainedCamera& f = frames[i];
    if (f.name.empty() || !isFile(f.name)) continue;
    uint32_t width = 0, height = 0;
    if (!readImageSize(f.name, width, height)) continue;  // not an image vknerf reads: named as it is
    const uint32_t k = downscaleOf(width, height, f.camera);
    if (k == 0)
      throw Error("camera " + std::to_string(i) + ": image '" + f.name + "' is " + std::to_string(width) + "x" +
                  std::to_string(height) + ", neither the " + std::to_string(f.camera.width) + "x" +
                  std::to_string(f.camera.height) + " it was trained at nor a multiple of it");
    Camera& c = f.camera;
    // The inverse of Dataset::load's downscale, which multiplies by the float 1/k.
    c.fx *= float(k);
    c.fy *= float(k);
    c.cx *= float(k);
    c.cy *= float(k);
    c.width = width;
    c.height = height;
    if (fs::path(f.name).is_relative()) f.name = relativeTo(f.name, folder);
  }
  return frames;
}

}  // namespace vknerf::nerf

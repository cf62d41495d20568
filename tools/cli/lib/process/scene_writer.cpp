#include "lib/process/scene_writer.h"

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "vknerf/image_io.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"

namespace fs = std::filesystem;

namespace vknerf::process {
namespace {

nlohmann::json lensKeys(const Lens& l) {
  nlohmann::json j;
  switch (l.model) {
    case LensModel::Pinhole:
      j["camera_model"] = "PINHOLE";
      break;
    case LensModel::OpenCV:
      // instant-ngp's keys are k1 k2 p1 p2; k3 (OpenCV's r^6) only when COLMAP's model has it.
      // The rational terms of FULL_OPENCV have no key in the format.
      if (l.k4 != 0 || l.k5 != 0 || l.k6 != 0)
        throw Error("the camera's lens has rational terms (k4..k6) that transforms.json cannot state; "
                    "choose --camera-model OPENCV");
      j = {{"camera_model", "OPENCV"}, {"k1", l.k1}, {"k2", l.k2}, {"p1", l.p1}, {"p2", l.p2}};
      if (l.k3 != 0) j["k3"] = l.k3;
      break;
    case LensModel::Fisheye:
      j = {{"camera_model", "OPENCV_FISHEYE"}, {"is_fisheye", true}, {"k1", l.k1}, {"k2", l.k2}, {"k3", l.k3}, {"k4", l.k4}};
      break;
  }
  return j;
}

}  // namespace

fs::path stagingFolder(const fs::path& target) {
  fs::path t = target;
  if (!t.has_filename()) t = t.parent_path();  // "scene/" names the folder "scene"
  return t.parent_path() / ("." + t.filename().string() + ".partial-" + std::to_string(::getpid()));
}

SceneBox writeTransforms(const fs::path& scene, uint32_t downscale,
                         const std::function<void(size_t, size_t)>& progress) {
  DatasetOptions options;
  options.split = "all";
  options.downscale = downscale;
  const size_t passes = downscale > 1 ? 2 : 1;  // decoding, then writing the copies
  if (progress) options.progress = [&](size_t done, size_t total) { progress(done, passes * total); };
  const Dataset d = Dataset::load((scene / "sparse" / "0").string(), options);
  const std::string folder = downscale > 1 ? "images_" + std::to_string(downscale) : "images";
  if (downscale > 1) fs::create_directories(scene / folder);

  // COLMAP shares one camera between all images (single_camera): the first states it for all.
  const Camera& c0 = d.cameras.at(0);
  nlohmann::json j = lensKeys(c0.lens);
  j["fl_x"] = c0.fx, j["fl_y"] = c0.fy, j["cx"] = c0.cx, j["cy"] = c0.cy, j["w"] = c0.width, j["h"] = c0.height;
  j["aabb"] = {{d.bounds.min[0], d.bounds.min[1], d.bounds.min[2]}, {d.bounds.max[0], d.bounds.max[1], d.bounds.max[2]}};
  j["frames"] = nlohmann::json::array();
  for (size_t i = 0; i < d.cameras.size(); ++i) {
    const Camera& c = d.cameras[i];
    if (c.fx != c0.fx || c.fy != c0.fy || c.cx != c0.cx || c.cy != c0.cy || c.width != c0.width || c.height != c0.height)
      throw Error("'" + d.names[i] + "' has a camera of its own; the scene expects one shared camera");
    fs::path file = fs::path(d.names[i]).filename();
    if (downscale > 1) {
      file.replace_extension(".png");  // lossless: the copy is what training compares with
      vknerf::savePng((scene / folder / file).string(), d.images[i]);
      if (progress) progress(d.cameras.size() + i + 1, 2 * d.cameras.size());
    }
    nlohmann::json m = nlohmann::json::array();
    for (int r = 0; r < 4; ++r) m.push_back({c.c2w[4 * r], c.c2w[4 * r + 1], c.c2w[4 * r + 2], c.c2w[4 * r + 3]});
    j["frames"].push_back({{"file_path", folder + "/" + file.string()}, {"transform_matrix", m}});
  }
  writeFileAtomically((scene / "transforms.json").string(), j.dump(2) + "\n");
  return {d.bounds, d.boundsSource};
}

void checkReplaceable(const fs::path& target) {
  std::error_code ec;
  if (!fs::exists(target, ec)) return;
  if (!fs::is_directory(target, ec))
    throw Error("'" + target.string() + "' exists and is not a folder; refusing to replace it with a scene");
  if (fs::is_empty(target, ec)) return;
  if (fs::is_regular_file(target / "colmap.log", ec) && fs::is_directory(target / "sparse", ec)) return;
  throw Error("'" + target.string() + "' exists and is not a scene vknerf process wrote (no colmap.log and sparse/ in "
              "it); refusing to replace it: choose a new folder");
}

void publishScene(const fs::path& staging, const fs::path& target) {
  std::error_code ec;
  fs::path old;
  if (fs::exists(target, ec)) {
    old = stagingFolder(target).string() + "-replaced";
    fs::rename(target, old, ec);
    if (ec) throw Error("cannot move the existing '" + target.string() + "' aside: " + ec.message());
  }
  fs::rename(staging, target, ec);
  if (ec) {
    std::error_code back;
    if (!old.empty()) fs::rename(old, target, back);
    throw Error("cannot rename '" + staging.string() + "' to '" + target.string() + "': " + ec.message());
  }
  if (!old.empty()) fs::remove_all(old, ec);
}

}  // namespace vknerf::process

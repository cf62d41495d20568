// Dataset::load: find the format, read the poses, load the images, complete the intrinsics, downscale,
// and find the scene box. The formats themselves live in src/io/ (transforms_json.cpp, colmap_*.cpp,
// llff_scene.cpp), the steps in src/io/dataset/ (read_scene.cpp, frame_camera.cpp, load_images.cpp),
// the box in dataset_bounds.cpp.
#include <algorithm>
#include <thread>

#include "io/dataset/dataset_loaders.h"
#include "io/dataset/memory_fit.h"
#include "vknerf/error.h"
#include "vknerf/image_io.h"

namespace vknerf {

using namespace io::detail;

Dataset Dataset::load(const std::string& pathString, const DatasetOptions& options) {
  if (options.downscale == 0) throw Error("DatasetOptions.downscale must be at least 1, got 0");
  if (options.split != "train" && options.split != "val" && options.split != "test" && options.split != "all")
    throw Error("DatasetOptions.split must be train, val, test or all, got '" + options.split + "'");
  if (!(options.holdoutFraction >= 0 && options.holdoutFraction < 1))
    throw Error("DatasetOptions.holdoutFraction must be in [0, 1), got " + std::to_string(options.holdoutFraction));

  SceneSpec scene = readScene(fs::path(pathString), options);
  checkOnePosePerImage(scene);
  if (scene.frames.empty())
    throw Error("dataset '" + pathString + "': split '" + options.split + "' is empty");

  // Image sizes first (headers only), so that a bad file or too little memory is reported before
  // anything is decoded.
  const uint32_t n = uint32_t(scene.frames.size());
  // The factor left to apply here: less, or none, when the reader found smaller images already.
  const uint32_t downscale = scene.downscale.value_or(options.downscale);
  std::vector<std::pair<uint32_t, uint32_t>> sizes(n);
  for (uint32_t i = 0; i < n; ++i) {
    const FrameSpec& f = scene.frames[i];
    if (f.image.empty()) throw Error(f.where + ": image not found: " + f.imageTried);
    if (!vknerf::readImageSize(f.image.string(), sizes[i].first, sizes[i].second))
      vknerf::loadImage(f.image.string());  // throws with stb's reason
  }
  // The decoded set must fit in host memory, with one full-resolution image per decoding thread.
  {
    uint64_t largest = 0;
    for (const auto& sz : sizes) largest = std::max(largest, io::rgba8Bytes(std::span(&sz, 1)));
    const uint32_t threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    std::vector<io::ImageSize> loaded;
    for (const auto& [w, h] : sizes) loaded.emplace_back(w / downscale, h / downscale);
    io::requireFit("loading '" + pathString + "'", loaded, largest * std::min<uint64_t>(threads, n),
                     "decoding buffers", io::availableHostBytes(), "host memory (available)",
                     options.downscale);
  }

  Dataset d;
  std::vector<Camera> fullRes;
  for (uint32_t i = 0; i < n; ++i) fullRes.push_back(completeCamera(scene.frames[i], sizes[i].first, sizes[i].second));

  d.images = loadImages(scene.frames, downscale, options);
  for (uint32_t i = 0; i < n; ++i) {
    if (d.images[i].width != sizes[i].first / downscale || d.images[i].height != sizes[i].second / downscale)
      throw Error("image '" + scene.frames[i].image.string() + "' changed size while loading");
    d.cameras.push_back(downscaledCamera(fullRes[i], downscale, d.images[i].width, d.images[i].height));
    d.names.push_back(scene.frames[i].image.string());
    if (scene.frames[i].depthBounds) d.depthBounds.push_back(*scene.frames[i].depthBounds);
  }

  if (scene.hasBox) {
    d.bounds = scene.box;
    d.boundsSource = scene.boxSource;
    d.aabbScale = scene.aabbScale;
  } else {
    // Every camera of the scene (all splits) places the box, so that the splits agree on it.
    std::vector<Camera> all = fullRes;
    for (const FrameSpec& f : scene.others) {
      uint32_t w = f.intrinsics.width, h = f.intrinsics.height;
      if ((!w || !h) && (f.image.empty() || !vknerf::readImageSize(f.image.string(), w, h))) continue;
      try {
        all.push_back(completeCamera(f, w, h));
      } catch (const Error&) {
        // Another split's flaw is reported when that split is loaded; here it only loses a camera.
      }
    }
    d.bounds = boxFromCameras(all);
    d.boundsSource = carveWithAlpha(d.cameras, d.images, d.bounds) ? "cameras+alpha" : "cameras";
  }
  return d;
}

}  // namespace vknerf

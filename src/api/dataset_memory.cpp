// Dataset::fromMemory: cameras and images an application already holds, checked as the loaders
// check what they read, the box placed as for a scene file that states none.
#include <cmath>
#include <string>

#include "io/dataset/dataset_loaders.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"

namespace vknerf {

namespace {

bool positiveFinite(float v) { return std::isfinite(v) && v > 0; }

void checkCamera(const Camera& c, const ImageRGBA8& image, const std::string& where) {
  if (!positiveFinite(c.fx) || !positiveFinite(c.fy))
    throw Error(where + ": focal lengths must be finite and positive, got fx = " + std::to_string(c.fx) +
                ", fy = " + std::to_string(c.fy));
  if (!std::isfinite(c.cx) || !std::isfinite(c.cy)) throw Error(where + ": principal point must be finite");
  for (float v : c.c2w)
    if (!std::isfinite(v)) throw Error(where + ": camera-to-world matrix must be finite");
  if (image.width == 0 || image.height == 0) throw Error(where + ": image is empty");
  if (image.rgba.size() != size_t(image.width) * image.height * 4)
    throw Error(where + ": image holds " + std::to_string(image.rgba.size()) + " bytes, not width x height x 4 = " +
                std::to_string(size_t(image.width) * image.height * 4));
  if (c.width != image.width || c.height != image.height)
    throw Error(where + ": camera is " + std::to_string(c.width) + "x" + std::to_string(c.height) + " but its image is " +
                std::to_string(image.width) + "x" + std::to_string(image.height));
  checkLens(c, where);
}

}  // namespace

Dataset Dataset::fromMemory(std::vector<Camera> cameras, std::vector<ImageRGBA8> images, std::vector<std::string> names,
                            std::optional<Aabb> bounds) {
  if (cameras.empty()) throw Error("dataset from memory: no cameras");
  if (images.size() != cameras.size())
    throw Error("dataset from memory: " + std::to_string(cameras.size()) + " cameras but " +
                std::to_string(images.size()) + " images");
  if (!names.empty() && names.size() != cameras.size())
    throw Error("dataset from memory: " + std::to_string(cameras.size()) + " cameras but " +
                std::to_string(names.size()) + " names");
  for (size_t i = 0; i < cameras.size(); ++i)
    checkCamera(cameras[i], images[i], "dataset from memory: camera " + std::to_string(i));
  Dataset d;
  if (names.empty())
    for (size_t i = 0; i < cameras.size(); ++i) names.push_back("image " + std::to_string(i));
  d.cameras = std::move(cameras);
  d.images = std::move(images);
  d.names = std::move(names);
  if (bounds) {
    for (int a = 0; a < 3; ++a)
      if (!(std::isfinite(bounds->min[a]) && std::isfinite(bounds->max[a]) && bounds->min[a] < bounds->max[a]))
        throw Error("dataset from memory: the box's min must be below its max on every axis, finite");
    d.bounds = *bounds;
    d.boundsSource = "given";
  } else {
    d.bounds = io::detail::boxFromCameras(d.cameras);
    d.boundsSource = io::detail::carveWithAlpha(d.cameras, d.images, d.bounds) ? "cameras+alpha" : "cameras";
  }
  return d;
}

}  // namespace vknerf

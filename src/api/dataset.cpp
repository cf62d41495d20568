// Dataset::load: find the format, read the poses, load the images, complete the intrinsics, downscale,
// and find the scene box. The formats themselves live in transforms_json.cpp, colmap_*.cpp and
// llff_scene.cpp, the box in dataset_bounds.cpp.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <mutex>
#include <thread>
#include <tuple>

#include "io/dataset/dataset_loaders.h"
#include "vknerf/image_io.h"
#include "io/dataset/memory_fit.h"
#include "vknerf/error.h"

namespace vknerf {
namespace io::detail {

std::vector<size_t> holdoutIndices(size_t n, float fraction, const std::string& split) {
  std::vector<size_t> all(n);
  for (size_t i = 0; i < n; ++i) all[i] = i;
  if (split == "all" || n == 0) return all;
  size_t held = fraction > 0 ? std::max<size_t>(1, size_t(std::lround(double(fraction) * double(n)))) : 0;
  held = std::min(held, n);
  std::vector<bool> isHeld(n, false);
  // Evenly spaced, centred in each of `held` equal runs; distinct because n / held >= 1.
  for (size_t j = 0; j < held; ++j) isHeld[size_t((double(j) + 0.5) * double(n) / double(held))] = true;
  std::vector<size_t> out;
  bool wantHeld = split != "train";
  for (size_t i = 0; i < n; ++i)
    if (isHeld[i] == wantHeld) out.push_back(i);
  return out;
}

void checkRigid(const std::array<double, 16>& m, const std::string& where, const char* field) {
  for (double v : m)
    if (!std::isfinite(v)) throw Error(where + ": " + field + " has a non-finite entry");
  // 1e-3 accepts matrices printed with 4+ significant digits and catches any scale, shear or mirror
  // a pose could carry by mistake.
  constexpr double kTol = 1e-3;
  double worst = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += m[4 * k + a] * m[4 * k + b];
      worst = std::max(worst, std::fabs(dot - (a == b ? 1.0 : 0.0)));
    }
  if (worst > kTol)
    throw Error(where + ": " + field + " rotation part is not orthonormal (|R^T R - I| = " +
                std::to_string(worst) + "); poses must be rigid");
  double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
               m[2] * (m[4] * m[9] - m[5] * m[8]);
  if (std::fabs(det - 1) > kTol)
    throw Error(where + ": " + field + " rotation part has determinant " + std::to_string(det) +
                " (a reflection); poses must be rigid");
  if (std::fabs(m[12]) > kTol || std::fabs(m[13]) > kTol || std::fabs(m[14]) > kTol || std::fabs(m[15] - 1) > kTol)
    throw Error(where + ": " + field + " last row is not (0, 0, 0, 1)");
}

float asDeviceFloat(double v, const FrameSpec& f, const char* field) {
  if (!(std::fabs(v) <= kDeviceLimit)) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", v);
    throw Error(f.where + ": " + field + " value " + value + " is beyond the range the device computes with (|x| <= 1e15)");
  }
  return float(v);
}

Camera completeCamera(const FrameSpec& f, uint32_t width, uint32_t height) {
  const Intrinsics& in = f.intrinsics;
  if ((in.width && in.width != width) || (in.height && in.height != height))
    throw Error(f.where + ": image '" + f.image.string() + "' is " + std::to_string(width) + "x" +
                std::to_string(height) + " but the camera says " + std::to_string(in.width) + "x" +
                std::to_string(in.height));
  // A resized copy of the image the intrinsics are stated for scales them axis by axis; both axes
  // must have shrunk alike, to within the rounding of one pixel.
  double sx = 1, sy = 1;
  if (in.statedWidth && in.statedHeight) {
    const double sw = in.statedWidth, sh = in.statedHeight;
    if (std::fabs(double(height) * sw - double(width) * sh) > std::max(sw, sh))
      throw Error(f.where + ": image '" + f.image.string() + "' is " + std::to_string(width) + "x" + std::to_string(height) +
                  ", not a copy of the " + std::to_string(in.statedWidth) + "x" + std::to_string(in.statedHeight) +
                  " the camera states scaled alike in width and height");
    // A folder of copies N times smaller holds them at the stated size over N, however rounded: a
    // size further off is a copy of other photos than those the intrinsics are stated for.
    if (const double n = in.statedFactor) {
      for (const auto& [got, stated, field] : {std::tuple{double(width), sw, &in.statedWidthField},
                                               std::tuple{double(height), sh, &in.statedHeightField}})
        if (!(std::fabs(got * n - stated) < n)) {
          char want[32];
          std::snprintf(want, sizeof want, "%g", stated / n);
          throw Error(f.where + ": image '" + f.image.string() + "' is " + std::to_string(width) + "x" +
                      std::to_string(height) + " but " + *field + " " + std::to_string(uint32_t(stated)) + " / " +
                      std::to_string(in.statedFactor) + " is " + want + ": its folder should hold the photos " +
                      std::to_string(in.statedFactor) + " times smaller than the " + std::to_string(in.statedWidth) +
                      "x" + std::to_string(in.statedHeight) + " the camera states");
        }
    }
    sx = double(width) / sw;
    sy = double(height) / sh;
  }
  double fx = in.fx * sx, fy = in.fy * sy;
  if (!std::isfinite(fx) && std::isfinite(in.angleX)) fx = 0.5 * width / std::tan(0.5 * in.angleX);
  if (!std::isfinite(fy) && std::isfinite(in.angleY)) fy = 0.5 * height / std::tan(0.5 * in.angleY);
  if (!std::isfinite(fx)) fx = fy;  // square pixels when only one focal length is stated
  if (!std::isfinite(fy)) fy = fx;
  if (!std::isfinite(fx)) throw Error(f.where + ": no focal length (" + in.focalFieldX + ")");
  if (!(fx > 0) || !(fy > 0)) throw Error(f.where + ": focal length must be positive");
  Camera c;
  // The focal length the file states is named first: the other may be derived from it.
  const bool xStated = std::isfinite(in.fx) || std::isfinite(in.angleX);
  const std::string fieldX = "focal length x (" + in.focalFieldX + ")", fieldY = "focal length y (" + in.focalFieldY + ")";
  if (!xStated) c.fy = asDeviceFloat(fy, f, fieldY.c_str());
  c.fx = asDeviceFloat(fx, f, fieldX.c_str());
  c.fy = asDeviceFloat(fy, f, fieldY.c_str());
  if (!(c.fx > 0) || !(c.fy > 0)) throw Error(f.where + ": focal length is too small for 32-bit floats");
  c.cx = asDeviceFloat(std::isfinite(in.cx) ? in.cx * sx : 0.5 * width, f, "principal point cx");
  c.cy = asDeviceFloat(std::isfinite(in.cy) ? in.cy * sy : 0.5 * height, f, "principal point cy");
  c.width = width;
  c.height = height;
  for (int i = 0; i < 16; ++i) c.c2w[i] = asDeviceFloat(f.c2w[i], f, f.poseField.c_str());
  // The coefficients are dimensionless, so the check at full resolution holds for every downscale:
  // the grid runs from edge to edge of the image, which bounds every pixel centre at any scale.
  c.lens = in.lens;
  checkLens(c, f.where);
  return c;
}

}  // namespace io::detail

namespace {

using namespace io::detail;

bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}
bool isDir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}

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

// An image listed twice with two poses (a copied frame whose file_path was not changed) would train
// on both, each pulling the field its own way: an error naming both entries. The same pose twice is
// only repetition, and is let through. Every split counts: the scene is one set of photos.
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

// Loads (and box-filters by `downscale`) every frame's image, options.threads (default: every core)
// at a time; rethrows the first failure in frame order so the message does not depend on thread
// timing.
std::vector<ImageRGBA8> loadImages(const std::vector<FrameSpec>& frames, uint32_t downscale, const DatasetOptions& options) {
  std::vector<ImageRGBA8> images(frames.size());
  std::vector<std::exception_ptr> errors(frames.size());
  std::atomic<size_t> next{0};
  size_t done = 0;
  std::mutex progressLock;
  auto work = [&] {
    for (size_t i; (i = next++) < frames.size();) {
      try {
        const FrameSpec& f = frames[i];
        if (f.image.empty()) throw Error(f.where + ": image not found: " + f.imageTried);
        ImageRGBA8 img = vknerf::loadImage(f.image.string());
        if (img.width < downscale || img.height < downscale)
          throw Error("image '" + f.image.string() + "' (" + std::to_string(img.width) + "x" +
                      std::to_string(img.height) + ") is smaller than the downscale factor " + std::to_string(downscale));
        images[i] = downscale > 1 ? vknerf::downscaleImage(img, downscale) : std::move(img);
      } catch (...) {
        errors[i] = std::current_exception();
      }
      if (options.progress) {
        std::lock_guard<std::mutex> hold(progressLock);
        options.progress(++done, frames.size());
      }
    }
  };
  const size_t cores = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  const size_t threads = std::min<size_t>(frames.size(), cores);
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
  return images;
}

}  // namespace

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
    Camera c = fullRes[i];
    // A downscaled pixel covers `downscale` full-resolution pixels, so its centre is at
    // downscale * (x + 0.5) in full-resolution pixels: every intrinsic divides by the factor.
    const float s = 1.0f / float(downscale);
    c.fx *= s;
    c.fy *= s;
    c.cx *= s;
    c.cy *= s;
    c.width = d.images[i].width;
    c.height = d.images[i].height;
    d.cameras.push_back(c);
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

#include "lib/process/process.h"

#include <chrono>

#include "lib/process/input_images.h"
#include "lib/process/report.h"
#include "lib/process/scene_writer.h"
#include "lib/process/sparse_model.h"
#include "lib/process/subsample.h"
#include "lib/process/video_frames.h"
#include "vknerf/error.h"

namespace fs = std::filesystem;

namespace vknerf::process {
namespace {

// Removes the staging folder unless it has been published; keeps COLMAP's log beside SCENE.
class Staging {
 public:
  Staging(const fs::path& target) : target_(target), path_(stagingFolder(target)) {
    std::error_code ec;
    fs::remove_all(path_, ec);
    fs::create_directories(path_, ec);
    if (ec) throw Error("cannot create '" + path_.string() + "': " + ec.message());
  }
  ~Staging() {
    if (published_) return;
    std::error_code ec;
    // An empty log (COLMAP never started: not installed) tells nothing the error does not.
    if (fs::exists(log(), ec) && fs::file_size(log(), ec) > 0) fs::rename(log(), keptLog(), ec);
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  fs::path log() const { return path_ / "colmap.log"; }
  // Where the log is kept after a failure, the path errors name.
  std::string keptLog() const { return target_.string() + ".colmap.log"; }
  void publish() {
    publishScene(path_, target_);
    published_ = true;
  }

 private:
  fs::path target_, path_;
  bool published_ = false;
};

// A message naming the staged log names the log kept after the failure instead.
std::string withKeptLog(std::string message, const Staging& staging) {
  const std::string staged = staging.log().string();
  for (size_t at; (at = message.find(staged)) != std::string::npos;) message.replace(at, staged.size(), staging.keptLog());
  return message;
}

Matcher chooseMatcher(const std::string& name, bool video) {
  if (name == "exhaustive") return Matcher::exhaustive;
  if (name == "sequential") return Matcher::sequential;
  if (name == "auto") return video ? Matcher::sequential : Matcher::exhaustive;
  throw Error("--matcher must be auto, exhaustive or sequential, got '" + name + "'");
}

void say(const ProcessObserver& observer, const std::string& line) {
  if (observer.say) observer.say(line);
}

// The images COLMAP gets: --max-images of them evenly spread, at least 3.
std::vector<fs::path> imagesToUse(std::vector<fs::path> images, const ProcessOptions& o, const ProcessObserver& observer) {
  const size_t found = images.size();
  if (o.maxImages) {
    std::vector<fs::path> kept;
    for (size_t i : evenSubsample(images.size(), o.maxImages)) kept.push_back(images[i]);
    images.swap(kept);
  }
  if (images.size() < 3)
    throw Error("'" + o.input + "' gives " + std::to_string(images.size()) +
                " images; COLMAP needs at least 3 (JPEG or PNG files, or a video)");
  if (images.size() < found)
    say(observer, "kept " + std::to_string(images.size()) + " of " + std::to_string(found) + " images (--max-images)");
  return images;
}

// `photos`: the photos of a folder, already chosen and decoded; empty for a video.
std::string run(const ProcessOptions& o, const ProcessObserver& observer, Staging& staging, std::vector<fs::path> photos) {
  const auto start = std::chrono::steady_clock::now();
  std::error_code ec;
  const bool video = photos.empty();
  ColmapSettings colmap = o.colmap;
  colmap.matcher = chooseMatcher(o.matcher, video);

  std::vector<fs::path> images = std::move(photos);
  if (video) {
    VideoFrameOptions v;
    v.fps = o.fps;
    v.logPath = staging.log().string();
    v.progress = observer.framesScored;
    images = extractSharpFrames(o.input, staging.path() / "colmap" / "frames", v);
    say(observer, "video: " + std::to_string(images.size()) + " frames kept (the sharpest of every " +
                      std::to_string(v.candidatesPerFrame) + ")");
    images = imagesToUse(std::move(images), o, observer);
  }
  placeImages(images, staging.path() / "images");
  if (video) fs::remove_all(staging.path() / "colmap" / "frames", ec);

  const ColmapPaths paths{staging.path() / "images", staging.path() / "colmap" / "database.db",
                          staging.path() / "colmap" / "sparse", staging.log()};
  runColmap(paths, colmap, images.size(), observer.stage);

  const auto model = largestModel(paths.sparse);
  if (!model || model->registeredImages == 0)
    throw Error("COLMAP made no model from " + std::to_string(images.size()) +
                " images (too few matches between them); log: " + staging.log().string());
  const size_t needed = registeredNeeded(images.size(), o.minRegisteredShare);
  if (model->registeredImages < needed)
    throw Error("COLMAP registered " + std::to_string(model->registeredImages) + " of " + std::to_string(images.size()) +
                " images (at least " + std::to_string(needed) + " needed); log: " + staging.log().string());
  fs::create_directories(staging.path() / "sparse", ec);
  fs::rename(model->folder, staging.path() / "sparse" / "0", ec);
  if (ec) throw Error("cannot move the model '" + model->folder.string() + "': " + ec.message());

  const SceneBox box = writeTransforms(staging.path(), o.downscale, observer.sceneImages);
  staging.publish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ModelSummary published = *model;
  published.folder = fs::path(o.output) / "sparse" / "0";
  return processReport(published, images.size(), box, seconds);
}

}  // namespace

std::string processCapture(const ProcessOptions& o, const ProcessObserver& observer) {
  std::error_code ec;
  if (!fs::exists(o.input, ec)) throw Error("'" + o.input + "' does not exist (a folder of photos or a video)");
  if (o.downscale == 0) throw Error("--downscale must be at least 1");
  if (!(o.minRegisteredShare >= 0 && o.minRegisteredShare <= 1)) throw Error("--min-registered must be in [0, 1]");
  if (o.output.empty()) throw Error("no output scene (-o)");
  checkReplaceable(o.output);
  // Photos are chosen and decoded before anything is created: a photo vknerf cannot read is named
  // now, not found by COLMAP minutes later. A video's frames are extracted into the staging folder.
  std::vector<fs::path> photos;
  if (fs::is_directory(o.input, ec)) {
    photos = imagesToUse(listImages(o.input), o, observer);
    checkImagesDecode(photos, o.input);
    say(observer, "photos: " + std::to_string(photos.size()) + " decoded");
  }
  Staging staging(o.output);
  try {
    return run(o, observer, staging, std::move(photos));
  } catch (const Error& e) {
    throw Error(withKeptLog(e.what(), staging));
  }
}

}  // namespace vknerf::process

#pragma once
// COLMAP's sparse reconstruction as three runs of Debian's `colmap` (3.8, built without CUDA):
// SIFT features on the CPU with one camera shared by every image, matching, incremental mapping.
// Headless: Qt is told to draw offscreen, so no display is needed.
#include <filesystem>
#include <functional>
#include <string>

#include "lib/process/colmap_log.h"

namespace vknerf::process {

enum class Matcher {
  exhaustive,  // every pair: best for photos from anywhere around the object, cost grows as n^2
  sequential,  // each image with its next neighbours (vocabulary-free, no loop detection): video
};

struct ColmapSettings {
  std::string cameraModel = "OPENCV";  // COLMAP's name: OPENCV, SIMPLE_RADIAL, PINHOLE, OPENCV_FISHEYE, ...
  Matcher matcher = Matcher::exhaustive;
  // SIFT sees images scaled down to this longest side. COLMAP's default (3200) spends most of its
  // time on detail a NeRF's poses do not need; features and matching cost grow with the pixels.
  unsigned siftMaxImageSize = 1600;
  unsigned siftMaxFeatures = 2048;  // per image; COLMAP's CPU matcher spends most of the time on these
  unsigned sequentialOverlap = 10;  // neighbours each video frame is matched with
};

struct ColmapPaths {
  std::filesystem::path images, database, sparse, log;  // sparse/ is created; it receives 0/, 1/, ...
};

// Called as a stage starts, as its log moves it on, and once more when it has finished: the stage,
// its progress and the seconds since it started.
using StageReport = std::function<void(ColmapStage stage, const StageProgress& progress, double seconds, bool finished)>;

// Runs the stages in turn, `imageCount` images in `paths.images`. Throws vknerf::Error when colmap
// is not installed (naming the Debian package) or a stage fails (one line: the stage, the reason
// its log gives (failureReason) and the log).
void runColmap(const ColmapPaths& paths, const ColmapSettings& settings, size_t imageCount, const StageReport& report);

}  // namespace vknerf::process

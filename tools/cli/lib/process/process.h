#pragma once
// `vknerf process`: a folder of photos or a video in, a scene `vknerf train` reads out, through
// COLMAP (colmap_stages.h) and, for a video, ffmpeg (video_frames.h).
#include <cstdint>
#include <functional>
#include <string>

#include "lib/process/colmap_stages.h"

namespace vknerf::process {

struct ProcessOptions {
  std::string input;   // a folder of JPEG/PNG photos, or a video file
  std::string output;  // SCENE
  double fps = 2;            // video: frames kept per second
  uint32_t downscale = 1;    // > 1: also write images_N/ copies, which transforms.json then names
  size_t maxImages = 0;      // > 0: keep this many, evenly spread
  std::string matcher = "auto";  // "auto" (exhaustive for photos, sequential for a video), "exhaustive", "sequential"
  double minRegisteredShare = 0.5;  // fail when the largest model registers fewer of the images
  ColmapSettings colmap;
};

struct ProcessObserver {
  std::function<void(const std::string& line)> say;  // a finished step, one line
  StageReport stage;                                  // a COLMAP stage moving on
  std::function<void(size_t done, size_t total)> framesScored;  // video frames scored for sharpness
  std::function<void(size_t done, size_t total)> sceneImages;   // images read, then copies written (scene_writer.h)
};

// Runs everything and returns the report (report.h). Throws vknerf::Error with a one-line reason;
// SCENE is then untouched and COLMAP's log, when there is one, is kept as SCENE.colmap.log beside
// it, which the message names. Option values out of range are errors here too.
std::string processCapture(const ProcessOptions& options, const ProcessObserver& observer);

}  // namespace vknerf::process

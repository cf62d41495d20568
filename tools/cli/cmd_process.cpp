// `vknerf process PHOTOS|VIDEO -o SCENE`: camera poses for your own photos or video through COLMAP
// (tools/cli/lib/process/), written as a scene `vknerf train SCENE` reads.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "checks.h"
#include "command_files.h"
#include "command.h"
#include "lib/process/process.h"
#include "lib/process/subprocess.h"
#include "progress.h"

namespace vknerf::cli {
namespace {

const char* stageName(process::ColmapStage s) {
  switch (s) {
    case process::ColmapStage::features: return "features";
    case process::ColmapStage::exhaustiveMatching: return "matching (exhaustive)";
    case process::ColmapStage::sequentialMatching: return "matching (sequential)";
    case process::ColmapStage::mapping: return "mapping";
  }
  return "";
}

// One line per stage: rewritten in place on a terminal, else printed every few seconds and at the end.
process::StageReport stagePrinter() {
  const bool tty = ::isatty(fileno(stdout));
  auto last = std::make_shared<double>(-1e9);
  return [tty, last](process::ColmapStage stage, const process::StageProgress& p, double seconds, bool finished) {
    if (!tty && !finished && seconds - *last < 5) return;
    *last = finished ? -1e9 : seconds;
    char count[64] = "";
    if (p.total) std::snprintf(count, sizeof count, "%llu/%llu ", (unsigned long long)p.done, (unsigned long long)p.total);
    else if (p.done) std::snprintf(count, sizeof count, "%llu ", (unsigned long long)p.done);
    std::printf("%s%s: %s%s, %.1f s%s", tty ? "\r\033[K" : "", stageName(stage), count, process::progressUnit(stage), seconds,
                tty && !finished ? "" : "\n");
    std::fflush(stdout);
  };
}

Registration processCommand(
    "process", "Camera poses for your own photos or video with COLMAP: writes a scene vknerf train reads",
    [](CLI::App& app, const Globals&) {
      auto o = std::make_shared<process::ProcessOptions>();
      app.add_option("input", o->input, "A folder of JPEG/PNG photos, or a video file")->required();
      app.add_option("-o,--output", o->output, "The scene folder to write (replaced only when the new one is complete)")
          ->required();
      app.add_option("--fps", o->fps, "Video: frames kept per second, each the sharpest of 4 decoded (default 2)")
          ->check(PositiveFinite);
      app.add_option("--downscale", o->downscale,
                     "Also write images_N/ copies N times smaller, which transforms.json then names (default 1: none)")
          ->check(CLI::Range(1u, 64u));
      app.add_option("--max-images", o->maxImages, "Keep at most this many images, evenly spread (default 0: all)");
      app.add_option("--matcher", o->matcher, "auto (exhaustive for photos, sequential for a video), exhaustive or sequential")
          ->check(CLI::IsMember({"auto", "exhaustive", "sequential"}));
      app.add_option("--camera-model", o->colmap.cameraModel,
                     "COLMAP camera model shared by all images: OPENCV (default), SIMPLE_RADIAL, PINHOLE, OPENCV_FISHEYE, ...");
      app.add_option("--sift-max-size", o->colmap.siftMaxImageSize,
                     "Longest image side SIFT sees (default " + std::to_string(o->colmap.siftMaxImageSize) +
                         "; COLMAP's own 3200 is several times slower)")
          ->check(CLI::Range(64u, 10000u));
      app.add_option("--max-features", o->colmap.siftMaxFeatures,
                     "SIFT features per image (default " + std::to_string(o->colmap.siftMaxFeatures) +
                         "; CPU matching time grows with it)")
          ->check(CLI::Range(64u, 100000u));
      app.add_option("--min-registered", o->minRegisteredShare,
                     "Fail when COLMAP places fewer than this share of the images (default 0.5)")
          ->check(CLI::Range(0.0, 1.0));
      return [o, &app] {
        // Frames per second of a video: for a folder of photos it would do nothing, so it is refused.
        std::error_code ec;
        if (app.count("--fps") && std::filesystem::is_directory(o->input, ec))
          throw UsageError("process: --fps has no effect on a folder of photos (it chooses the frames of a video)");
        CommandFiles files("process");  // the photos (or video) must survive the scene replacing -o
        files.input(o->input, "input").replacedFolder(o->output, "-o");
        files.check();
        // A signal while COLMAP or ffmpeg runs is passed on and waited for, and the staging folder
        // is removed on the way out (exit 128 + signal): a stopped process leaves no child running.
        process::forwardStopSignals(process::Forwarding::whileAChildRuns);
        process::ProcessObserver observer;
        observer.say = [](const std::string& line) { std::printf("%s\n", line.c_str()); };
        observer.stage = stagePrinter();
        observer.framesScored = progressPrinter("scoring video frames");
        observer.sceneImages = progressPrinter("writing the scene: images");
        std::printf("%s", process::processCapture(*o, observer).c_str());
        std::printf("scene written to %s (train it with: vknerf train %s -o model.vknerf)\n", o->output.c_str(),
                    o->output.c_str());
        return 0;
      };
    });

}  // namespace
}  // namespace vknerf::cli

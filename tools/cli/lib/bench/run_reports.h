#pragma once
// What `bench scenes` reads of a finished train or eval run. A build with `train --summary` writes
// its numbers as JSON; an older build (b012119 and before) only prints them, so its log is parsed:
//   "  samples per ray (mean over all steps)            6.1"   (fast; vanilla: "(last step)")
//   "memory: host peak 812.3 MiB; device 95.2 MiB (model ...)"
//   "done after 200 steps (41.2 s, last train PSNR 24.10 dB); model saved to ..."
// eval's --json has had psnr, ssim, seconds_per_image and count in every build; samples_per_pixel
// (the field samples its renders shaded) since 2026-12.
#include <cstdint>
#include <optional>
#include <string>

namespace vknerf::bench {

struct TrainReport {
  std::optional<uint32_t> steps;
  std::optional<double> samplesPerRay;  // mean over all steps where the model counts it, else the last step's
  std::optional<double> deviceMiB;      // device buffers at the end of training: model + training images
};

// train --summary's JSON. Throws vknerf::Error naming `what` when it is not JSON or lacks steps.
TrainReport readTrainSummary(const std::string& json, const std::string& what);
// train's printed output; a number that is not there stays empty.
TrainReport parseTrainLog(const std::string& log);

struct EvalReport {
  double psnr = 0, ssim = 0, secondsPerView = 0;
  uint64_t views = 0;
  std::optional<double> samplesPerPixel;  // empty from a build that does not write it
};

// eval --json's file. Throws vknerf::Error naming `what` when a number is missing or not finite.
EvalReport readEvalJson(const std::string& json, const std::string& what);

}  // namespace vknerf::bench

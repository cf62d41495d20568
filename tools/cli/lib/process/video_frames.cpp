#include "lib/process/video_frames.h"

#include <sstream>

#include "vknerf/image_io.h"
#include "lib/process/input_images.h"
#include "lib/process/sharpness.h"
#include "lib/process/subprocess.h"
#include "vknerf/error.h"

namespace fs = std::filesystem;

namespace vknerf::process {

std::vector<fs::path> extractSharpFrames(const fs::path& video, const fs::path& scratch,
                                         const VideoFrameOptions& options) {
  if (!(options.fps > 0)) throw Error("--fps must be positive");
  std::error_code ec;
  fs::create_directories(scratch, ec);
  if (ec) throw Error("cannot create '" + scratch.string() + "': " + ec.message());
  std::ostringstream rate;
  rate.precision(17);
  rate << options.fps * std::max(1u, options.candidatesPerFrame);
  // High-quality JPEG (-q:v 2): small files, and no visible loss for SIFT or training.
  const int status = runLogged({{"ffmpeg", "-nostdin", "-hide_banner", "-loglevel", "error", "-i", video.string(), "-vf",
                                 "fps=" + rate.str(), "-q:v", "2", (scratch / "frame_%06d.jpg").string()},
                                {},
                                "ffmpeg",
                                options.logPath,
                                {}});
  throwIfStopped();  // ffmpeg was passed the signal: not its failure
  if (status != 0) {
    const std::string why = lastLogLine(options.logPath);
    throw Error("ffmpeg could not read frames from '" + video.string() + "'" + (why.empty() ? "" : " (" + why + ")") +
                "; log: " + options.logPath);
  }
  const std::vector<fs::path> candidates = listImages(scratch);
  if (candidates.empty()) throw Error("ffmpeg gave no frames from '" + video.string() + "'; log: " + options.logPath);
  std::vector<double> scores;
  for (const fs::path& c : candidates) {
    scores.push_back(varianceOfLaplacian(vknerf::loadImage(c.string())));
    if (options.progress) options.progress(scores.size(), candidates.size());
  }
  std::vector<fs::path> kept;
  for (size_t i : sharpestPerWindow(scores, options.candidatesPerFrame)) kept.push_back(candidates[i]);
  return kept;
}

}  // namespace vknerf::process

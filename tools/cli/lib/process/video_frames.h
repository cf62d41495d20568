#pragma once
// Frames of a video for COLMAP, through Debian's ffmpeg: `candidatesPerFrame` frames are decoded
// for every frame kept, and the sharpest of each such window (sharpness.h) is kept, so a blurred
// frame gives way to a neighbour within 1 / fps seconds.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace vknerf::process {

struct VideoFrameOptions {
  double fps = 2;                  // frames kept per second of video
  unsigned candidatesPerFrame = 4; // frames decoded (and scored) per frame kept
  std::string logPath;             // ffmpeg's output is appended here
  std::function<void(size_t done, size_t total)> progress;  // frames scored
};

// Decodes `video` into `scratch` (created, left holding the candidates) and returns the kept frames,
// in order. Throws vknerf::Error when ffmpeg is missing (naming the Debian package), fails (naming
// the log) or gives no frames.
std::vector<std::filesystem::path> extractSharpFrames(const std::filesystem::path& video,
                                                      const std::filesystem::path& scratch,
                                                      const VideoFrameOptions& options);

}  // namespace vknerf::process

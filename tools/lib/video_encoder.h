#pragma once
// H.264 video from rendered frames through Debian's `ffmpeg`, run as a subprocess that reads raw
// RGBA frames on a pipe. The video is written to a temporary file beside the target and renamed
// over it only when ffmpeg has finished cleanly, so a failed or interrupted encode never leaves a
// truncated video where a good one was.
#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace vknerf::nerf {

class VideoEncoder {
 public:
  // Starts ffmpeg for width x height frames at `fps`. Throws vknerf::Error when ffmpeg is not
  // installed (naming the Debian package) or cannot start. Odd sizes are padded by one black
  // row/column: yuv420p, which every player reads, needs even dimensions.
  VideoEncoder(const std::string& path, uint32_t width, uint32_t height, double fps);
  ~VideoEncoder();  // an encoder never finished is abandoned: ffmpeg stopped, temporary files removed
  VideoEncoder(const VideoEncoder&) = delete;
  VideoEncoder& operator=(const VideoEncoder&) = delete;

  // One frame, width * height * 4 bytes of RGBA8 (alpha ignored), rows top to bottom.
  void addFrame(const std::vector<uint8_t>& rgba);
  // Waits for ffmpeg, checks it succeeded, syncs the file and renames it over the target.
  void finish();

 private:
  [[noreturn]] void fail(const std::string& what);
  void abandon();

  std::string path_, tmp_, log_;
  uint32_t width_, height_;
  pid_t pid_ = -1;
  int pipe_ = -1;
  uint64_t frames_ = 0;
};

}  // namespace vknerf::nerf

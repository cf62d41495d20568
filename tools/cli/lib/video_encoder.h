#pragma once
// H.264 video from rendered frames through Debian's `ffmpeg`, run as a subprocess that reads raw
// RGBA frames on a pipe. ffmpeg writes a vknerf::TemporaryFile (vknerf/file_output.h), which
// becomes the video only when ffmpeg has finished cleanly, as every other output does: renamed over
// a regular file, copied into a special one (/dev/null, a pipe). A failed or interrupted encode never
// leaves a truncated video where a good one was, nor the temporary file or ffmpeg's log.
#include <sys/types.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "vknerf/file_output.h"

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
  // Waits for ffmpeg, checks it succeeded, and puts the video in place (TemporaryFile::commit).
  void finish();

 private:
  [[noreturn]] void fail(const std::string& what);
  void abandon();
  void forgetWriter();

  std::string path_;
  std::unique_ptr<TemporaryFile> video_, log_;  // what ffmpeg writes: the video, and its messages
  uint32_t width_, height_;
  pid_t pid_ = -1;
  int pipe_ = -1;
  uint64_t frames_ = 0;
};

}  // namespace vknerf::nerf

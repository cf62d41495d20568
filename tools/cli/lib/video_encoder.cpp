#include "lib/video_encoder.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <sstream>

#include "lib/process/subprocess.h"
#include "vknerf/error.h"

extern char** environ;

namespace vknerf::nerf {
VideoEncoder::VideoEncoder(const std::string& path, uint32_t width, uint32_t height, double fps)
    : path_(path), width_(width), height_(height) {
  if (width == 0 || height == 0) throw Error(path + ": cannot encode a video of empty frames");
  if (!(fps > 0 && fps <= 1000)) throw Error(path + ": frame rate must be in (0, 1000], got " + std::to_string(fps));
  video_ = std::make_unique<TemporaryFile>(path);
  log_ = std::make_unique<TemporaryFile>(path, ".log");
  // A pipe whose reader has died must fail a write with EPIPE, not kill vknerf.
  ::signal(SIGPIPE, SIG_IGN);
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw Error(path + ": cannot start ffmpeg: " + std::strerror(errno));
  std::ostringstream size, rate;
  size << width << "x" << height;
  rate.precision(17);
  rate << fps;
  const std::vector<std::string> args = {
      "ffmpeg", "-nostdin", "-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba",
      "-s", size.str(), "-r", rate.str(), "-i", "pipe:0", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2",
      "-c:v", "libx264", "-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4", video_->path()};
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, log_->fd(), 2);
  // ffmpeg is named as the file's writer before a signal can remove the file: otherwise it would
  // outlive vknerf and create the file again. It starts with no signal held.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  TemporaryFilesBusy::withNoSignalHeld(attributes);
  int err = 0;
  {
    TemporaryFilesBusy starting;
    err = posix_spawnp(&pid_, "ffmpeg", &actions, &attributes, argv.data(), environ);
    if (err == 0) video_->setWriter(pid_), log_->setWriter(pid_);
  }
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[0]);
  if (err != 0) {
    ::close(fds[1]);
    pid_ = -1;
    if (err == ENOENT)
      throw Error(path + ": cannot encode video: ffmpeg is not installed (Debian package: ffmpeg)");
    throw Error(path + ": cannot start ffmpeg: " + std::strerror(err));
  }
  pipe_ = fds[1];
}

VideoEncoder::~VideoEncoder() { abandon(); }

// ffmpeg has been reaped: its process id may be reused, and a signal must not stop that process.
void VideoEncoder::forgetWriter() {
  pid_ = -1;
  video_->setWriter(0);
  log_->setWriter(0);
}

void VideoEncoder::abandon() {
  if (pipe_ >= 0) ::close(pipe_), pipe_ = -1;
  if (pid_ > 0) {
    ::kill(pid_, SIGTERM);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    forgetWriter();
  }
  video_->discard();
  log_->discard();
}

void VideoEncoder::fail(const std::string& what) {
  const std::string why = process::lastLogLine(log_->path());
  abandon();
  throw Error(path_ + ": " + what + (why.empty() ? "" : " (ffmpeg: " + why + ")"));
}

void VideoEncoder::addFrame(const std::vector<uint8_t>& rgba) {
  if (pipe_ < 0) throw Error(path_ + ": the video is already finished");
  if (rgba.size() != size_t(width_) * height_ * 4)
    throw Error(path_ + ": frame " + std::to_string(frames_) + " is not " + std::to_string(width_) + "x" +
                std::to_string(height_) + " RGBA");
  const char* p = reinterpret_cast<const char*>(rgba.data());
  size_t n = rgba.size();
  while (n > 0) {
    ssize_t w = ::write(pipe_, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      fail("ffmpeg stopped reading frames at frame " + std::to_string(frames_) + ": " + std::strerror(errno));
    }
    p += w;
    n -= size_t(w);
  }
  ++frames_;
}

void VideoEncoder::finish() {
  if (pipe_ < 0) throw Error(path_ + ": the video is already finished");
  ::close(pipe_);
  pipe_ = -1;
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  forgetWriter();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) fail("ffmpeg failed to encode the video");
  if (frames_ == 0) fail("no frames to encode");
  try {
    video_->commit();
  } catch (const Error&) {
    abandon();
    throw;
  }
  log_->discard();
}

}  // namespace vknerf::nerf

// Outputs: the atomic writer reports every failure and never leaves a partial file, and the depth
// colour map survives depths and ranges that are not finite.
#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>

#include "lib/csv.h"
#include "lib/render_output.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"

extern char** environ;

namespace fs = std::filesystem;

namespace {

// A fresh folder of this process's under the temporary directory, removed with its contents when
// the test ends, passed or failed (ctest runs each test in its own process).
struct ScratchDir {
  fs::path path;
  explicit ScratchDir(const std::string& name)
      : path(fs::temp_directory_path() / ("vknerf_output_" + std::to_string(::getpid())) / name) {
    fs::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path.parent_path(), ec);
  }
};

std::string contents(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(FileOutput, ReplacesTheTargetAndLeavesNoTemporaryFile) {
  const ScratchDir scratch("replace");
  const fs::path& dir = scratch.path;
  const auto target = (dir / "out.json").string();
  vknerf::writeFileAtomically(target, std::string("old"));
  vknerf::writeFileAtomically(target, std::string("new content"));
  EXPECT_EQ(contents(target), "new content");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
}

TEST(FileOutput, FullDeviceIsAnErrorNamingThePath) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  try {
    vknerf::writeFileAtomically("/dev/full", std::string(100000, 'x'));
    FAIL() << "writing to /dev/full succeeded";
  } catch (const vknerf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/full"), std::string::npos) << e.what();
  }
}

TEST(FileOutput, MissingFolderAndFolderTargetAreErrors) {
  const ScratchDir scratch("missing");
  const fs::path& dir = scratch.path;
  EXPECT_THROW(vknerf::writeFileAtomically((dir / "no" / "x.csv").string(), std::string("a")), vknerf::Error);
  EXPECT_THROW(vknerf::writeFileAtomically(dir.string(), std::string("a")), vknerf::Error);
  EXPECT_THROW(vknerf::checkOutputPath((dir / "no" / "x.csv").string(), "--csv"), vknerf::Error);
  EXPECT_THROW(vknerf::checkOutputPath(dir.string(), "--csv"), vknerf::Error);
  EXPECT_NO_THROW(vknerf::checkOutputPath((dir / "x.csv").string(), "--csv"));
  EXPECT_NO_THROW(vknerf::checkOutputPath("/dev/null", "--csv"));
}

TEST(FileOutput, DepthColourMapToleratesNonFiniteDepthsAndRanges) {
  // A NaN radius or a camera at 1e39 gives NaN or infinite depths and depth ranges; the colour map
  // once used them as a table index.
  const ScratchDir scratch("depth");
  const fs::path& dir = scratch.path;
  vknerf::RenderedImage img;
  img.width = 4;
  img.height = 2;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  img.depth = {nan, inf, -inf, 0.5f, 1e30f, -1e30f, 0.0f, 2.0f};
  img.opacity.assign(8, 1.0f);
  img.rgb.assign(24, 0.5f);
  const std::pair<float, float> ranges[] = {{nan, nan}, {0.0f, inf}, {-inf, inf}, {inf, inf}, {0.0f, 1.0f}};
  for (auto [lo, hi] : ranges) {
    const auto path = (dir / "depth.png").string();
    vknerf::nerf::saveDepthPng(path, img, lo, hi);
    EXPECT_GT(fs::file_size(path), 0u);
  }
}

TEST(FileOutput, SheetDepthRangeSpansTheOpaquePixelsOfEveryView) {
  // Two views: opaque depths 1..100 shared between them, a NaN among them, and transparent pixels
  // at 1000 (the far field) that the range must not reach.
  vknerf::RenderedImage a, b;
  for (int d = 1; d <= 100; ++d) {
    vknerf::RenderedImage& v = d % 2 ? a : b;
    v.depth.push_back(float(d));
    v.opacity.push_back(0.9f);
    v.depth.push_back(1000.0f);
    v.opacity.push_back(0.2f);
  }
  a.depth.push_back(std::numeric_limits<float>::quiet_NaN());
  a.opacity.push_back(1.0f);
  const auto range = vknerf::nerf::depthRangeOfOpaquePixels({&a, &b}, 0.05f);
  ASSERT_TRUE(range.has_value());
  EXPECT_FLOAT_EQ(range->nearDepth, 6.0f);   // the 5% quantile of 1..100: index 4.95 -> 5 -> depth 6
  EXPECT_FLOAT_EQ(range->farDepth, 95.0f);   // index 94.05 -> 94 -> depth 95
  vknerf::RenderedImage clear;
  clear.depth = {1.0f, 2.0f};
  clear.opacity = {0.1f, 0.4f};
  EXPECT_FALSE(vknerf::nerf::depthRangeOfOpaquePixels({&clear}).has_value());
}

TEST(FileOutput, CsvFieldsAreQuotedPerRfc4180) {
  EXPECT_EQ(vknerf::nerf::csvField("r_0.png"), "r_0.png");
  EXPECT_EQ(vknerf::nerf::csvField("a,b"), "\"a,b\"");
  EXPECT_EQ(vknerf::nerf::csvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(vknerf::nerf::csvField("two\nlines"), "\"two\nlines\"");
}

// A file another program fills: gone on every way out but commit(), which renames it over a regular
// target and copies it into a special one (a pipe here), which stays what it was.
TEST(FileOutput, TemporaryFileIsCommittedOrRemoved) {
  const ScratchDir scratch("temporary");
  const fs::path& dir = scratch.path;
  const std::string target = (dir / "video.mp4").string();
  std::string kept;
  {
    vknerf::TemporaryFile tmp(target, ".log");
    kept = tmp.path();
    EXPECT_EQ(kept.rfind(target + ".tmp.", 0), 0u) << kept;
    EXPECT_TRUE(fs::exists(kept));
  }
  EXPECT_FALSE(fs::exists(kept));  // an error or exception on the way: removed
  {
    vknerf::TemporaryFile tmp(target);
    kept = tmp.path();
    ASSERT_EQ(::write(tmp.fd(), "frames", 6), 6);
    // What a signal handler does, in a process that then ends (no file is made after it).
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) vknerf::removeTemporaryFiles(), ::_exit(0);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_FALSE(fs::exists(kept));
  }
  {
    vknerf::TemporaryFile tmp(target);
    std::ofstream(tmp.path()) << "encoded";  // written by its name, as ffmpeg does
    tmp.commit();
  }
  EXPECT_EQ(contents(target), "encoded");
  const std::string pipe = (dir / "pipe").string();
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = contents(pipe); });
  {
    vknerf::TemporaryFile tmp(pipe);
    EXPECT_EQ(fs::path(tmp.path()).parent_path(), fs::temp_directory_path());  // not beside a special file
    std::ofstream(tmp.path()) << "streamed";
    tmp.commit();
    EXPECT_FALSE(fs::exists(tmp.path()));
  }
  reader.join();
  EXPECT_EQ(received, "streamed");
  struct stat st;
  ASSERT_EQ(::stat(pipe.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 2);  // video.mp4 and the pipe
}

// A signal while the program filling a temporary file is being started: the file's removal waits
// until the program is named its writer, so the program is stopped first and cannot make the file
// again after the process has ended. The signal is handled on another thread, as on Vulkan's.
TEST(FileOutput, SignalWhileAWriterStartsLeavesNoFile) {
  const ScratchDir scratch("writer_starting");
  const std::string target = (scratch.path / "video.mp4").string();
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    vknerf::removeTemporaryFilesOnSignals();
    std::thread([] {
      for (;;) ::pause();
    }).detach();
    vknerf::TemporaryFile tmp(target);
    {
      vknerf::TemporaryFilesBusy starting;
      // The writer makes the file again after a while, as ffmpeg opens its output.
      const std::string script = "sleep 0.5; echo late > \"$0\"";
      const char* argv[] = {"sh", "-c", script.c_str(), tmp.path().c_str(), nullptr};
      posix_spawnattr_t attributes;
      posix_spawnattr_init(&attributes);
      vknerf::TemporaryFilesBusy::withNoSignalHeld(attributes);
      pid_t writer = -1;
      if (posix_spawnp(&writer, "sh", nullptr, &attributes, const_cast<char**>(argv), environ) != 0) ::_exit(3);
      if (::write(ready[1], "s", 1) != 1) ::_exit(4);
      ::usleep(300000);  // the signal comes meanwhile
      tmp.setWriter(writer);
    }
    for (;;) ::pause();  // the signal ends the process
  }
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  ::close(ready[0]);
  ::close(ready[1]);
  ASSERT_EQ(::kill(child, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "status " << status;
  ::usleep(1000000);  // past the time an orphaned writer would make the file again
  EXPECT_EQ(std::distance(fs::directory_iterator(scratch.path), fs::directory_iterator{}), 0);
}

// Up front: a folder files go into exists and takes them, or can be made under the nearest folder
// that exists; a file on the way or a place that takes no new file (/proc, even for root) is refused.
TEST(FileOutput, OutputFoldersAreCheckedWithoutBeingMade) {
  const ScratchDir scratch("folders");
  const fs::path& dir = scratch.path;
  EXPECT_NO_THROW(vknerf::checkOutputFolder(dir.string(), "-o"));
  EXPECT_NO_THROW(vknerf::checkOutputFolder((dir / "a" / "b").string(), "-o"));
  EXPECT_FALSE(fs::exists(dir / "a"));
  std::ofstream(dir / "file") << "x";
  EXPECT_THROW(vknerf::checkOutputFolder((dir / "file").string(), "-o"), vknerf::Error);
  EXPECT_THROW(vknerf::checkOutputFolder((dir / "file" / "sub").string(), "-o"), vknerf::Error);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);  // no probe left
  if (fs::is_directory("/proc")) {
    EXPECT_THROW(vknerf::checkOutputFolder("/proc/vknerf_renders", "-o"), vknerf::Error);
    EXPECT_THROW(vknerf::checkOutputPath("/proc/vknerf.json", "--json"), vknerf::Error);
  }
}

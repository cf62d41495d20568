// `vknerf process`: the pure parts (sharpness, subsampling, COLMAP log progress, the largest model,
// transforms.json agreeing with the COLMAP model), the error paths with a fake or missing colmap,
// and one run of the real colmap on rendered views whose recovered poses are compared with the
// true ones after a similarity alignment.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "vknerf/image_io.h"
#include "lib/process/colmap_log.h"
#include "lib/process/process.h"
#include "lib/process/report.h"
#include "lib/process/scene_writer.h"
#include "lib/process/sharpness.h"
#include "lib/process/sparse_model.h"
#include "lib/process/subsample.h"
#include "lib/process/video_frames.h"
#include "support/cli_run.h"
#include "support/colmap_model_files.h"
#include "support/dataset_checks.h"
#include "support/similarity_alignment.h"
#include "support/temp_dir.h"
#include "support/textured_views.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"

namespace fs = std::filesystem;
using namespace vknerf;
using namespace vknerf::process;
using vknerf::test::expectSameCameras;
using vknerf::test::TempDirTest;

namespace {

ImageRGBA8 greyImage(uint32_t w, uint32_t h, const std::vector<uint8_t>& grey) {
  ImageRGBA8 img{w, h, {}};
  for (uint8_t g : grey) img.rgba.insert(img.rgba.end(), {g, g, g, 255});
  return img;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

// Replaces PATH for the scope of a test: a fake colmap, or none at all.
struct PathOverride {
  std::string saved = std::getenv("PATH") ? std::getenv("PATH") : "";
  explicit PathOverride(const fs::path& dir) { setenv("PATH", dir.c_str(), 1); }
  ~PathOverride() { setenv("PATH", saved.c_str(), 1); }
};

bool colmapInstalled() { return std::system("command -v colmap > /dev/null 2>&1") == 0; }

}  // namespace

TEST(ProcessSharpness, VarianceOfLaplacianMatchesAHandComputation) {
  // 3x4 grey image: the interior is (1,1) and (2,1). Laplacians: at (1,1) 10 + 50 + 20 + 30 - 4*40 = -50,
  // at (2,1) 20 + 60 + 40 + 0 - 4*30 = 0; mean -25, variance ((-25)^2 + 25^2) / 2 = 625.
  const ImageRGBA8 img = greyImage(4, 3, {0, 10, 20, 0,  //
                                          20, 40, 30, 0,  //
                                          0, 50, 60, 0});
  EXPECT_DOUBLE_EQ(varianceOfLaplacian(img), 625.0);
  EXPECT_EQ(varianceOfLaplacian(greyImage(2, 2, {1, 2, 3, 4})), 0.0);
  // A sharp checkerboard scores higher than the same board box-blurred.
  std::vector<uint8_t> sharp, blurred;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) sharp.push_back(((x / 2 + y / 2) % 2) ? 200 : 40);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      int sum = 0;
      for (int d = -1; d <= 1; ++d) sum += sharp[y * 16 + std::clamp(x + d, 0, 15)];
      blurred.push_back(uint8_t(sum / 3));
    }
  EXPECT_GT(varianceOfLaplacian(greyImage(16, 16, sharp)), 2 * varianceOfLaplacian(greyImage(16, 16, blurred)));
}

TEST(ProcessSharpness, SharpestOfEachWindow) {
  EXPECT_EQ(sharpestPerWindow({1, 5, 2, 9, 9, 0, 3}, 3), (std::vector<size_t>{1, 3, 6}));
  EXPECT_EQ(sharpestPerWindow({4, 4}, 0), (std::vector<size_t>{0, 1}));
  EXPECT_TRUE(sharpestPerWindow({}, 4).empty());
}

// A real video through ffmpeg: 16 frames at 8 frames/s, one sharp checkerboard in each window of 4
// and the rest box-blurred; at --fps 2 with 4 candidates per frame kept, the sharp ones are kept.
TEST(ProcessVideo, KeepsTheSharpestFrameOfEachWindow) {
  if (std::system("ffmpeg -version > /dev/null 2>&1") != 0) GTEST_SKIP() << "ffmpeg is not installed here";
  test::TempDir dir("video");
  const uint32_t w = 64, h = 48;
  const std::vector<size_t> sharpFrames{1, 6, 8, 15};
  for (size_t f = 0; f < 16; ++f) {
    std::vector<uint8_t> board;
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) board.push_back((((x + f) / 4 + y / 4) % 2) ? 220 : 30);
    const bool sharp = std::find(sharpFrames.begin(), sharpFrames.end(), f) != sharpFrames.end();
    std::vector<uint8_t> grey = board;
    if (!sharp)  // a 5x5 box blur: what camera shake does to the Laplacian
      for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
          int sum = 0;
          for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx)
              sum += board[std::clamp(int(y) + dy, 0, int(h) - 1) * w + std::clamp(int(x) + dx, 0, int(w) - 1)];
          grey[y * w + x] = uint8_t(sum / 25);
        }
    char name[32];
    std::snprintf(name, sizeof name, "f_%02zu.png", f);
    vknerf::savePng(dir.file(name), greyImage(w, h, grey));
  }
  // ffv1: lossless, so the blur the test made is the blur the video holds.
  const std::string encode = "ffmpeg -nostdin -loglevel error -framerate 8 -i " + dir.file("f_%02d.png") +
                             " -c:v ffv1 " + dir.file("video.mkv");
  ASSERT_EQ(std::system(encode.c_str()), 0);
  VideoFrameOptions o;
  o.fps = 2;
  o.candidatesPerFrame = 4;
  o.logPath = dir.file("ffmpeg.log");
  size_t scored = 0;
  o.progress = [&](size_t done, size_t) { scored = done; };
  const auto kept = extractSharpFrames(dir.file("video.mkv"), dir.file("frames"), o);
  EXPECT_EQ(scored, 16u);
  ASSERT_EQ(kept.size(), sharpFrames.size());
  for (size_t i = 0; i < kept.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06zu.jpg", sharpFrames[i] + 1);  // ffmpeg counts from 1
    EXPECT_EQ(kept[i].filename().string(), name) << "window " << i;
  }
}

TEST(ProcessSubsample, EvenSpreadWithBothEnds) {
  EXPECT_EQ(evenSubsample(10, 4), (std::vector<size_t>{0, 3, 6, 9}));
  EXPECT_EQ(evenSubsample(5, 0), (std::vector<size_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(evenSubsample(3, 7), (std::vector<size_t>{0, 1, 2}));
  EXPECT_EQ(evenSubsample(9, 1), (std::vector<size_t>{0}));
  const auto k = evenSubsample(1000, 37);
  ASSERT_EQ(k.size(), 37u);
  for (size_t i = 1; i < k.size(); ++i) EXPECT_GT(k[i], k[i - 1]);
  EXPECT_EQ(k.back(), 999u);
}

TEST(ProcessLog, ProgressOfEachStage) {
  StageProgress p;
  EXPECT_TRUE(readProgressLine(ColmapStage::features, "Processed file [12/45]", p));
  EXPECT_EQ(p.done, 12u);
  EXPECT_EQ(p.total, 45u);
  EXPECT_FALSE(readProgressLine(ColmapStage::features, "  Name:            frame_0000.png", p));
  EXPECT_FALSE(readProgressLine(ColmapStage::features, "Processed file [12/45]", p));  // no move

  p = {};
  EXPECT_TRUE(readProgressLine(ColmapStage::exhaustiveMatching, "Matching block [2/3, 1/3] in 0.512s", p));
  EXPECT_EQ(p.done, 4u);
  EXPECT_EQ(p.total, 9u);
  EXPECT_TRUE(readProgressLine(ColmapStage::exhaustiveMatching, "Matching block [3/3, 3/3]", p));
  EXPECT_EQ(p.done, 9u);

  p = {};
  EXPECT_TRUE(readProgressLine(ColmapStage::sequentialMatching, "Matching image [7/30] in 0.1s", p));
  EXPECT_EQ(p.done, 7u);
  EXPECT_EQ(p.total, 30u);

  p = {};
  p.total = 45;
  EXPECT_TRUE(readProgressLine(ColmapStage::mapping, "Registering image #21 (3)", p));
  EXPECT_EQ(p.done, 3u);
  EXPECT_EQ(p.total, 45u);
  EXPECT_FALSE(readProgressLine(ColmapStage::mapping, "Processed file [1/2]", p));  // another stage's line
  EXPECT_FALSE(readProgressLine(ColmapStage::mapping, "Registering image #", p));
}

// The reason in a failed run's log: COLMAP 3.8's own words for a crash (its matcher on a database
// without features) and for a mapper that made nothing, never a stack trace's last frame.
TEST(ProcessLog, FailureReasonIsTheLogsErrorNotItsStackTrace) {
  const test::TempDir dir("colmap_log");
  const fs::path log = dir.path() / "colmap.log";
  std::ofstream(log) << "\n==============================================================================\n"
                        "Exhaustive feature matching\n"
                        "==============================================================================\n\n"
                        "F20261127 12:42:32.474221 17150 cache.h:132] Check failed: max_num_elems > 0 (0 vs. 0) \n"
                        "*** Check failure stack trace: ***\n"
                        "    @     0x7fa6ef0b41ed  google::LogMessage::Fail()\n"
                        "    @     0x7fa6ecd278ec  (unknown)\n";
  EXPECT_EQ(failureReason(log.string()), "Check failed: max_num_elems > 0 (0 vs. 0)");
  std::ofstream(log) << "Loading images... 0 in 0.000s (connected 0)\n\nElapsed time: 0.000 [minutes]\n\n"
                        "WARNING: No images with matches found in the database.\n\n"
                        "ERROR: failed to create sparse model\n";
  EXPECT_EQ(failureReason(log.string()), "ERROR: failed to create sparse model");
  std::ofstream(log) << "Processed file [1/3]\nsomething else broke\n";
  EXPECT_EQ(failureReason(log.string()), "something else broke");
  EXPECT_EQ(failureReason((dir.path() / "none.log").string()), "");
}

TEST(ProcessReport, RegistrationThresholdAndReportLines) {
  EXPECT_EQ(registeredNeeded(4, 0.5), 3u);
  EXPECT_EQ(registeredNeeded(45, 0.5), 23u);
  EXPECT_EQ(registeredNeeded(10, 0.5), 5u);
  ModelSummary m{"x", 40, 4197, 0.52};
  const std::string r = processReport(m, 45, {{{-1, -0.5, -0.25}, {1, 0.5, 0.25}}, "points3D"}, 12.5);
  EXPECT_NE(r.find("registered 40 of 45 images\n"), std::string::npos) << r;
  EXPECT_NE(r.find("mean reprojection error 0.520 px"), std::string::npos) << r;
  EXPECT_NE(r.find("4197 points"), std::string::npos) << r;
  EXPECT_NE(r.find("scene box [-1.000 -0.500 -0.250] .. [1.000 0.500 0.250] (from points3D"), std::string::npos) << r;
}

namespace {

// A COLMAP model of `images` views on a circle, with `points` points of error 0.25 + 0.5 * (i % 2).
test::ColmapModelRecords ringModel(int images, int points, uint64_t width = 64, uint64_t height = 48) {
  test::ColmapModelRecords m;
  m.cameras.push_back({1, "OPENCV", width, height, {50, 52, 31.5, 24.5, -0.05, 0.01, 0.001, -0.002}});
  for (int i = 0; i < images; ++i) {
    const double a = 2 * M_PI * i / images, c = std::cos(a), s = std::sin(a);
    // Looks at the origin from (4c, 1, 4s): back = position direction, OpenGL convention.
    const double bx = c, bz = s, rx = s, rz = -c;
    const std::array<double, 16> c2w = {rx, 0, bx, 4 * c, 0, 1, 0, 1, rz, 0, bz, 4 * s, 0, 0, 0, 1};
    m.images.push_back(test::imageRecord(uint32_t(i + 1), c2w, 1, "img_" + std::to_string(10 + i) + ".png"));
  }
  for (int i = 0; i < points; ++i) {
    test::ColmapPointRecord p;
    p.id = uint64_t(i + 1);
    p.xyz = {0.3 * std::sin(i * 1.7), 0.2 * std::cos(i * 0.9), 0.25 * std::sin(i * 2.3 + 1)};
    p.error = 0.25 + 0.5 * (i % 2);
    p.track = {{1, uint32_t(i)}, {2, uint32_t(i)}};
    m.points.push_back(p);
  }
  return m;
}

void writeImages(const fs::path& folder, const test::ColmapModelRecords& m) {
  fs::create_directories(folder);
  for (const auto& img : m.images) {
    ImageRGBA8 im{uint32_t(m.cameras[0].width), uint32_t(m.cameras[0].height), {}};
    for (uint32_t i = 0; i < im.width * im.height; ++i) im.rgba.insert(im.rgba.end(), {uint8_t(i * 7), uint8_t(i * 3), 90, 255});
    vknerf::savePng((folder / img.name).string(), im);
  }
}

}  // namespace

class ProcessScene : public TempDirTest {};

TEST_F(ProcessScene, LargestModelAndItsSummary) {
  test::writeColmapBinary(dir() / "sparse" / "0", ringModel(5, 20));
  test::writeColmapBinary(dir() / "sparse" / "1", ringModel(9, 10));
  test::writeColmapBinary(dir() / "sparse" / "2", ringModel(9, 12));
  const auto best = largestModel(dir() / "sparse");
  ASSERT_TRUE(best);
  EXPECT_EQ(best->folder, dir() / "sparse" / "2");
  EXPECT_EQ(best->registeredImages, 9u);
  EXPECT_EQ(best->points, 12u);
  EXPECT_DOUBLE_EQ(best->meanReprojectionError, 0.5);
  EXPECT_FALSE(largestModel(dir() / "nothing"));
}

// transforms.json states exactly the cameras (lens included) and box vknerf reads from the COLMAP
// model, at full resolution and for the images_N copies of --downscale N.
TEST_F(ProcessScene, TransformsJsonGivesTheCamerasOfTheColmapModel) {
  const auto model = ringModel(6, 30);
  for (uint32_t downscale : {1u, 2u}) {
    const fs::path scene = dir() / ("scene" + std::to_string(downscale));
    test::writeColmapBinary(scene / "sparse" / "0", model);
    writeImages(scene / "images", model);
    std::vector<std::pair<size_t, size_t>> progress;
    const SceneBox box = writeTransforms(scene, downscale, [&](size_t done, size_t total) { progress.emplace_back(done, total); });
    EXPECT_EQ(box.source, "points3D");
    // Every image decoded, then (downscale 2) every copy written, counted as one run.
    const size_t total = model.images.size() * (downscale > 1 ? 2 : 1);
    ASSERT_EQ(progress.size(), total);
    for (size_t i = 0; i < total; ++i) EXPECT_EQ(progress[i], std::make_pair(i + 1, total));
    DatasetOptions all;
    all.split = "all";
    all.downscale = downscale;
    const Dataset fromColmap = Dataset::load((scene / "sparse" / "0").string(), all);
    all.downscale = 1;
    const Dataset fromJson = Dataset::load((scene / "transforms.json").string(), all);
    expectSameCameras(fromColmap, fromJson);
    EXPECT_EQ(fromColmap.cameras[0].lens.model, LensModel::OpenCV);
    for (size_t i = 0; i < fromJson.images.size(); ++i) EXPECT_EQ(fromJson.images[i].rgba, fromColmap.images[i].rgba);
    // The folder itself now reads as transforms.json, with the same training split.
    const Dataset train = Dataset::load(scene.string());
    DatasetOptions trainColmap;
    trainColmap.downscale = downscale;
    expectSameCameras(Dataset::load((scene / "sparse" / "0").string(), trainColmap), train);
  }
}

TEST_F(ProcessScene, AnExistingSceneIsReplacedOnlyByACompleteOne) {
  const fs::path target = dir() / "scene";
  fs::create_directories(target);
  std::ofstream(target / "keep.txt") << "old";
  const fs::path staging = stagingFolder(target);
  EXPECT_EQ(staging.parent_path(), dir());
  EXPECT_EQ(staging.filename().string().rfind(".scene.partial-", 0), 0u) << staging;
  fs::create_directories(staging);
  std::ofstream(staging / "new.txt") << "new";
  publishScene(staging, target);
  EXPECT_TRUE(fs::exists(target / "new.txt"));
  EXPECT_FALSE(fs::exists(target / "keep.txt"));
  EXPECT_FALSE(fs::exists(staging));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir()), fs::directory_iterator()), 1);  // nothing left aside
}

namespace {

// A folder of `n` small photos.
fs::path photos(const fs::path& dir, int n) {
  const fs::path p = dir / "photos";
  fs::create_directories(p);
  for (int i = 0; i < n; ++i) vknerf::savePng((p / ("p" + std::to_string(i) + ".png")).string(), {8, 8, std::vector<uint8_t>(256, 128)});
  return p;
}

// A scene an earlier run wrote (what may be replaced), with a file of its own that must survive.
void earlierScene(const fs::path& scene) {
  fs::create_directories(scene / "sparse");
  std::ofstream(scene / "colmap.log") << "an earlier run";
  std::ofstream(scene / "keep.txt") << "old";
}

// The scene folder keeps its old content and no staging folder is left beside it.
void expectUntouched(const fs::path& dir, const fs::path& scene) {
  EXPECT_TRUE(fs::exists(scene / "keep.txt"));
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << e.path();
}

}  // namespace

TEST_F(ProcessScene, MissingColmapNamesTheDebianPackage) {
  const fs::path scene = dir() / "scene", empty = dir() / "empty";
  earlierScene(scene);
  fs::create_directories(empty);
  ProcessOptions o;
  o.input = photos(dir(), 3).string();
  o.output = scene.string();
  const PathOverride path(empty);
  EXPECT_EQ(errorOf([&] { processCapture(o, {}); }), "colmap is not installed (Debian package: colmap)");
  expectUntouched(dir(), scene);
  // A video needs ffmpeg first.
  const fs::path video = dir() / "clip.mp4";
  std::ofstream(video) << "not really";
  o.input = video.string();
  EXPECT_EQ(errorOf([&] { processCapture(o, {}); }), "ffmpeg is not installed (Debian package: ffmpeg)");
  expectUntouched(dir(), scene);
}

TEST_F(ProcessScene, FailingColmapNamesTheStageAndKeepsTheLog) {
  const fs::path scene = dir() / "scene", bin = dir() / "bin";
  earlierScene(scene);
  fs::create_directories(bin);
  {
    std::ofstream fake(bin / "colmap");
    fake << "#!/bin/sh\necho 'Processed file [1/3]'\necho 'E0101 something broke' >&2\nexit 3\n";
  }
  fs::permissions(bin / "colmap", fs::perms::owner_all);
  ProcessOptions o;
  o.input = photos(dir(), 3).string();
  o.output = scene.string();
  const PathOverride path(bin);
  const std::string log = scene.string() + ".colmap.log";
  EXPECT_EQ(errorOf([&] { processCapture(o, {}); }),
            "COLMAP failed at feature extraction (colmap feature_extractor, exit status 3): E0101 something broke; log: " +
                log);
  expectUntouched(dir(), scene);
  std::ifstream in(log);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("something broke"), std::string::npos) << text;

  // A colmap that succeeds but maps nothing.
  {
    std::ofstream fake(bin / "colmap");
    fake << "#!/bin/sh\nexit 0\n";
  }
  EXPECT_EQ(errorOf([&] { processCapture(o, {}); }),
            "COLMAP made no model from 3 images (too few matches between them); log: " + log);
  expectUntouched(dir(), scene);
}

// Only an empty folder or a scene an earlier run wrote is replaced: anything else is someone's data.
TEST_F(ProcessScene, SomeonesFolderIsNeverReplaced) {
  ProcessOptions o;
  o.input = photos(dir(), 3).string();
  o.output = (dir() / "documents").string();
  fs::create_directories(o.output);
  std::ofstream(dir() / "documents" / "letter.txt") << "dear";
  EXPECT_EQ(errorOf([&] { processCapture(o, {}); }),
            "'" + o.output + "' exists and is not a scene vknerf process wrote (no colmap.log and sparse/ in it); "
            "refusing to replace it: choose a new folder");
  EXPECT_TRUE(fs::exists(dir() / "documents" / "letter.txt"));
  o.output = (dir() / "letter.txt").string();
  std::ofstream(o.output) << "dear";
  EXPECT_NE(errorOf([&] { processCapture(o, {}); }).find("exists and is not a folder"), std::string::npos);
}

TEST_F(ProcessScene, TooFewImagesOrAMissingInput) {
  ProcessOptions o;
  o.input = photos(dir(), 2).string();
  o.output = (dir() / "scene").string();
  EXPECT_EQ(errorOf([&] { processCapture(o, {}); }),
            "'" + o.input + "' gives 2 images; COLMAP needs at least 3 (JPEG or PNG files, or a video)");
  EXPECT_FALSE(fs::exists(o.output));
  o.input = (dir() / "nope").string();
  EXPECT_NE(errorOf([&] { processCapture(o, {}); }).find("does not exist"), std::string::npos);
}

TEST(ProcessAlignment, RecoversAKnownSimilarity) {
  std::vector<std::array<double, 3>> from = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}, {1, 1, 1}};
  test::Similarity truth;
  const double a = 0.7, c = std::cos(a), s = std::sin(a);
  truth.R = {c, 0, s, 0, 1, 0, -s, 0, c};
  truth.s = 2.5;
  truth.t = {1, -2, 3};
  std::vector<std::array<double, 3>> to;
  for (const auto& p : from) to.push_back(truth.apply(p));
  const test::Similarity got = test::alignSimilarity(from, to);
  EXPECT_NEAR(got.s, 2.5, 1e-9);
  EXPECT_NEAR(test::rotationAngleDegrees(got.R, truth.R), 0, 1e-6);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got.t[k], truth.t[k], 1e-9);
}

// The worst camera of a COLMAP reconstruction against the true poses, after the best similarity:
// centre error over the scene size, and rotation error in degrees.
struct PoseErrors {
  double position = 1e30, angle = 1e30;
};

PoseErrors poseErrors(const Dataset& colmap, const std::vector<test::TrueView>& truth, double size) {
  std::vector<std::array<double, 3>> got, want;
  for (size_t i = 0; i < truth.size(); ++i) {
    EXPECT_EQ(fs::path(colmap.names[i]).filename(), truth[i].name);  // both in name order
    const auto& m = colmap.cameras[i].c2w;
    got.push_back({m[3], m[7], m[11]});
    want.push_back({truth[i].c2w[3], truth[i].c2w[7], truth[i].c2w[11]});
  }
  const test::Similarity align = test::alignSimilarity(got, want);
  PoseErrors e{0, 0};
  for (size_t i = 0; i < truth.size(); ++i) {
    const auto p = align.apply(got[i]);
    e.position = std::max(e.position, std::hypot(p[0] - want[i][0], p[1] - want[i][1], p[2] - want[i][2]) / size);
    std::array<double, 9> R{}, T{};
    const auto& m = colmap.cameras[i].c2w;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k) R[3 * r + c] += align.R[3 * r + k] * m[4 * k + c];
        T[3 * r + c] = truth[i].c2w[4 * r + c];
      }
    e.angle = std::max(e.angle, test::rotationAngleDegrees(R, T));
  }
  return e;
}

// The real colmap on 24 rendered 320x240 views (exhaustive matching, 512 features, SIFT at 320 px):
// every view registered, centres within 1% of the ring's diameter and orientations within 1 degree
// of the truth after the best similarity.
//
// COLMAP is not deterministic: its feature extraction and its matcher's RANSAC run on worker
// threads whose random generators are seeded from the clock (colmap/util/random.cc), so the
// database differs from run to run (the mapper on a given database is repeatable). Here 20 runs of
// 20 came out within 0.0021 and 0.25 degrees; one CI run of this test came out 84 degrees off. A
// conversion error (axes, c2w against w2c, the camera's convention) fails every run, so a run whose
// poses are off is repeated once, with the same bounds, and the test fails when both are off.
TEST_F(ProcessScene, RealColmapRecoversRenderedPoses) {
  if (!colmapInstalled()) GTEST_SKIP() << "colmap is not installed (Debian package: colmap); tools/dev/install-deps.sh installs it";
  const test::TexturedViewsSpec spec;
  const auto truth = test::renderTexturedViews(dir() / "photos", spec);
  PoseErrors worst;
  for (int attempt = 1; attempt <= 2; ++attempt) {
    const fs::path scene = dir() / ("scene" + std::to_string(attempt));
    const auto r = test::runCli("process " + (dir() / "photos").string() + " -o " + scene.string() +
                                " --max-features 512 --sift-max-size 320");
    if (r.code != 0) {  // COLMAP's own words, for whoever reads the failure
      std::ifstream in(scene.string() + ".colmap.log");
      std::string log((std::istreambuf_iterator<char>(in)), {});
      FAIL() << r.output << "\n--- colmap.log (end) ---\n" << log.substr(log.size() > 6000 ? log.size() - 6000 : 0);
    }
    EXPECT_NE(r.output.find("mapping:"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::exists(scene / "colmap.log"));
    DatasetOptions all;
    all.split = "all";
    const Dataset colmap = Dataset::load((scene / "sparse" / "0").string(), all);
    expectSameCameras(colmap, Dataset::load((scene / "transforms.json").string(), all));
    const bool registeredAll = r.output.find("registered 24 of 24 images") != std::string::npos;
    if (registeredAll) {
      ASSERT_EQ(colmap.cameras.size(), truth.size());
      worst = poseErrors(colmap, truth, 2 * spec.ringRadius);
    }
    std::printf("run %d: %s; worst camera centre error %.4f of the scene size, worst rotation error %.3f degrees\n",
                attempt, registeredAll ? "registered 24 of 24" : "not every view registered", worst.position,
                worst.angle);
    if (registeredAll && worst.position < 0.01 && worst.angle < 1.0) break;
    std::printf("%s\n", r.output.c_str());
  }
  EXPECT_LT(worst.position, 0.01);
  EXPECT_LT(worst.angle, 1.0);
}

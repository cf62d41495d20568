// `vknerf bench scenes` and `eval --sheet`: the reports read from train and eval (as this build
// writes them and as b012119 printed them), the names and order of runs, the table, the contact
// sheet's layout, and the command end to end on a tiny scene made from the sample scene's views,
// with a broken scene that must become a failed row and a non-zero exit.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "vknerf/image_io.h"
#include "lib/bench/run_plan.h"
#include "lib/bench/run_reports.h"
#include "lib/bench/scene_table.h"
#include "lib/contact_sheet.h"
#include "lib/render_output.h"
#include "support/cli_run.h"
#include "support/temp_dir.h"
#include "vknerf/error.h"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace vknerf;
using test::runCli;

namespace {

// What b012119's `vknerf train SCENE --config fast --steps 60 --downscale 2` printed at its end, as
// it printed it (the build whose binary has no --summary; `bench scenes` compares against it by
// reading this).
const char* const kB012119TrainTail = R"(model: 1 occupancy cascade(s) over the box (aabb_scale 1), device buffers 78.3 MiB
step     50  loss 0.00932  train PSNR 20.30 dB      143 rays/s  8:08 elapsed  ETA 1:37
step     60  loss 0.00705  train PSNR 21.52 dB      151 rays/s  8:15 elapsed  ETA 0:00
  occupied fraction                                0.426411
  occupied cells' bounding box / scene box (volume) 0.875
  samples per ray (last step)                      12.2
  samples per ray (mean over all steps)            18.9566
  rays per step (last step)                        1250
  samples per step (last step)                     15250
  samples kept by early termination (all steps)    0.987432
  parameters (hash grid)                           524288
  parameters (MLP)                                 3576
  device buffers MiB                               89.5946
memory: host peak 275.6 MiB; device 90.5 MiB (model 89.6 MiB + training images 1.0 MiB in 1 buffers)
done after 60 steps (496.2 s, last train PSNR 21.52 dB); model saved to /tmp/before.vknerf
)";

std::string readText(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::vector<std::string>> csvRows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::vector<std::string> fields{""};
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) fields.emplace_back();
      else fields.back() += c;
    }
    rows.push_back(fields);
  }
  return rows;
}

double finite(const std::string& field) {
  size_t used = 0;
  const double v = std::stod(field, &used);
  EXPECT_EQ(used, field.size()) << field;
  EXPECT_TRUE(std::isfinite(v)) << field;
  return v;
}

ImageRGBA8 solid(uint32_t w, uint32_t h, uint8_t v) { return {w, h, std::vector<uint8_t>(size_t(w) * h * 4, v)}; }

}  // namespace

TEST(BenchReports, ReadsB012119sPrintedTrainOutput) {
  const bench::TrainReport r = bench::parseTrainLog(kB012119TrainTail);
  ASSERT_TRUE(r.steps && r.samplesPerRay && r.deviceMiB);
  EXPECT_EQ(*r.steps, 60u);
  EXPECT_DOUBLE_EQ(*r.samplesPerRay, 18.9566);  // the mean over all steps, not the last step's
  EXPECT_DOUBLE_EQ(*r.deviceMiB, 90.5);         // model and training images, not the host's 275.6
  // Vanilla prints only the last step's samples per ray (a constant there); a stopped run says so.
  const bench::TrainReport v = bench::parseTrainLog(
      "  samples per ray (last step)                      192\ninterrupted after 7 steps (1.0 s, x); model saved to m\n");
  EXPECT_EQ(v.steps.value_or(0), 7u);
  EXPECT_DOUBLE_EQ(v.samplesPerRay.value_or(0), 192.0);
  EXPECT_FALSE(v.deviceMiB);
  EXPECT_FALSE(bench::parseTrainLog("vknerf: error: scene x: no such file\n").steps);
}

TEST(BenchReports, ReadsTheSummaryAndEvalJsonAndRefusesWhatLacksANumber) {
  const bench::TrainReport t = bench::readTrainSummary(
      R"({"steps": 12, "samples_per_ray": 9.5, "device_mib": 80.25, "train_psnr": null})", "s.json");
  EXPECT_EQ(t.steps.value_or(0), 12u);
  EXPECT_DOUBLE_EQ(t.samplesPerRay.value_or(0), 9.5);
  EXPECT_DOUBLE_EQ(t.deviceMiB.value_or(0), 80.25);
  EXPECT_THROW(bench::readTrainSummary(R"({"samples_per_ray": 9.5})", "s.json"), Error);
  EXPECT_THROW(bench::readTrainSummary("not json", "s.json"), Error);
  const bench::EvalReport e = bench::readEvalJson(
      R"({"psnr": 24.5, "ssim": 0.81, "seconds_per_image": 0.25, "count": 3, "images": []})", "e.json");
  EXPECT_DOUBLE_EQ(e.psnr, 24.5);
  EXPECT_DOUBLE_EQ(e.ssim, 0.81);
  EXPECT_DOUBLE_EQ(e.secondsPerView, 0.25);
  EXPECT_EQ(e.views, 3u);
  EXPECT_FALSE(e.samplesPerPixel);  // an older build's eval
  EXPECT_DOUBLE_EQ(bench::readEvalJson(R"({"psnr": 24.5, "ssim": 0.81, "seconds_per_image": 0.25, "count": 3,
                                          "samples_per_pixel": 41.5})", "e.json").samplesPerPixel.value_or(0), 41.5);
  EXPECT_THROW(bench::readEvalJson(R"({"psnr": 1, "ssim": 1, "seconds_per_image": 1, "count": 1, "samples_per_pixel": "x"})",
                                   "e.json"), Error);
  try {
    bench::readEvalJson(R"({"psnr": 24.5, "ssim": 0.81, "count": 3})", "e.json");
    ADD_FAILURE() << "no seconds_per_image";
  } catch (const Error& err) {
    EXPECT_NE(std::string(err.what()).find("seconds_per_image"), std::string::npos) << err.what();
  }
}

TEST(BenchPlan, NamesScenesByFolderAndBuildsByWhereTheirPathsDiffer) {
  const test::TempDir tmp("bench_plan");
  fs::create_directories(tmp.path() / "cup" / "sparse" / "0");
  std::ofstream(tmp.path() / "cup" / "transforms.json") << "{}";
  EXPECT_EQ(bench::sceneName(tmp.file("cup")), "cup");
  EXPECT_EQ(bench::sceneName(tmp.file("cup") + "/"), "cup");
  EXPECT_EQ(bench::sceneName(tmp.file("cup/transforms.json")), "cup");
  EXPECT_EQ(bench::sceneName(tmp.file("cup/sparse/0")), "cup");

  EXPECT_EQ(bench::buildNames({"/work/before/build/vknerf", "/work/wt/bench-scenes/build/vknerf"}),
            (std::vector<std::string>{"before", "bench-scenes"}));
  EXPECT_EQ(bench::buildNames({"/x/build/vknerf", "/x/build/vknerf-old"}), (std::vector<std::string>{"vknerf", "vknerf-old"}));
  EXPECT_EQ(bench::buildNames({"/src/project/build/vknerf"}), (std::vector<std::string>{"project"}));
  EXPECT_EQ(bench::buildNames({"old=/a/vknerf", "/b/vknerf"}), (std::vector<std::string>{"old", "b"}));
  EXPECT_EQ(bench::buildNames({"a b=/a/vknerf"}), (std::vector<std::string>{"a_b"}));
  EXPECT_EQ(bench::buildPath("old=/a/vknerf"), "/a/vknerf");
  EXPECT_EQ(bench::buildPath("/a=b/vknerf"), "/a=b/vknerf");  // '=' inside the path is part of it
  EXPECT_THROW(bench::buildNames({"x=/a/vknerf", "x=/b/vknerf"}), Error);

  EXPECT_EQ(bench::buildOrder(0, 2), (std::vector<size_t>{0, 1}));
  EXPECT_EQ(bench::buildOrder(1, 2), (std::vector<size_t>{1, 0}));
  EXPECT_EQ(bench::buildOrder(2, 3), (std::vector<size_t>{0, 1, 2}));
  EXPECT_EQ(bench::buildOrder(3, 1), (std::vector<size_t>{0}));
}

TEST(SceneTable, WritesEveryColumnAndLeavesWhatWasNotMeasuredEmpty) {
  bench::SceneRow ok{"cup", "before"};
  ok.psnr = 22.126, ok.ssim = 0.7, ok.steps = 1500, ok.samplesPerRay = 12.5, ok.secondsPerView = 3.25;
  ok.renderSamplesPerPixel = 7.3;
  ok.hostMiB = 900, ok.deviceMiB = 300.4, ok.sheet = "cup-before.png";
  bench::SceneRow failed{"broken", "before"};
  failed.failed = true, failed.status = "train failed (exit 1): vknerf: error: a, b | c";
  const auto rows = csvRows(bench::sceneTableCsv({ok, failed}));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].size(), 12u);
  EXPECT_EQ(rows[1], (std::vector<std::string>{"cup", "before", "22.1260", "0.70000", "1500", "12.500", "3.2500", "7.30",
                                               "900.0", "300.4", "cup-before.png", "ok"}));
  EXPECT_EQ(rows[2], (std::vector<std::string>{"broken", "before", "", "", "", "", "", "", "", "", "", failed.status}));
  const std::string md = bench::sceneTableMarkdown({ok, failed}, "Device: x");
  EXPECT_EQ(md.rfind("Device: x\n", 0), 0u) << md;
  EXPECT_NE(md.find("| cup | before | 22.13 | 0.700 | 1500 | 12.5 | 3.25 | 7.3 | 900 | 300 | [cup-before.png](<cup-before.png>) | ok |"),
            std::string::npos) << md;
  EXPECT_NE(md.find("| broken | before | - | - | - | - | - | - | - | - | - | train failed (exit 1): vknerf: error: a, b \\| c |"),
            std::string::npos) << md;
}

TEST(ContactSheet, TilesShrinkToFitAndAverageWhatTheyCover) {
  ImageRGBA8 stripes{4, 2, std::vector<uint8_t>(4 * 2 * 4)};
  for (uint32_t x = 0; x < 4; ++x)
    for (uint32_t y = 0; y < 2; ++y)
      for (int k = 0; k < 4; ++k) stripes.rgba[(y * 4 + x) * 4 + k] = x % 2 ? 200 : 100;
  const ImageRGBA8 small = nerf::fitInside(stripes, 2);
  EXPECT_EQ(small.width, 2u);
  EXPECT_EQ(small.height, 1u);
  for (uint8_t v : small.rgba) EXPECT_EQ(v, 150);
  EXPECT_EQ(nerf::fitInside(stripes, 8).rgba, stripes.rgba);  // never enlarged

  // The error map: 0 is the colour map's start, the full scale and beyond its end.
  const std::vector<float> truth(6, 0.5f), render{0.5f, 0.5f, 0.5f, 1.0f, 1.0f, 1.0f};
  const ImageRGBA8 err = nerf::errorRgba(render, truth, 2, 1, 0.25f);
  const auto lo = nerf::mapColour(0), hi = nerf::mapColour(1);
  EXPECT_EQ(std::vector<uint8_t>(err.rgba.begin(), err.rgba.begin() + 3), std::vector<uint8_t>(lo.begin(), lo.end()));
  EXPECT_EQ(std::vector<uint8_t>(err.rgba.begin() + 4, err.rgba.begin() + 7), std::vector<uint8_t>(hi.begin(), hi.end()));
}

TEST(ContactSheet, RowsOfFourTilesUnderTheirLabels) {
  using Sheet = nerf::ContactSheet;
  Sheet sheet({"a", "b", "c", "d"}, 32);
  sheet.addRow("one", {solid(64, 32, 10), solid(64, 32, 20), solid(64, 32, 30), solid(64, 32, 40)});  // shrunk to 32x16
  sheet.addRow("two", {solid(8, 8, 50), solid(8, 8, 60), solid(8, 8, 70), solid(8, 8, 80)});
  const ImageRGBA8 out = sheet.compose();
  EXPECT_EQ(out.width, Sheet::kGap + 4 * (32 + Sheet::kGap));
  EXPECT_EQ(out.height, Sheet::kGap + Sheet::kTextHeight + 2 * Sheet::kTextHeight + 16 + 8 + 2 * Sheet::kGap);
  const auto at = [&](uint32_t x, uint32_t y) { return out.rgba[(size_t(y) * out.width + x) * 4]; };
  const uint32_t row1 = Sheet::kGap + 2 * Sheet::kTextHeight, row2 = row1 + 16 + Sheet::kGap + Sheet::kTextHeight;
  for (uint32_t c = 0; c < 4; ++c) {
    const uint32_t x = Sheet::kGap + c * (32 + Sheet::kGap);
    EXPECT_EQ(at(x, row1), 10 * (c + 1));
    EXPECT_EQ(at(x + 31, row1 + 15), 10 * (c + 1));
    EXPECT_EQ(at(x, row2), 50 + 10 * c);
    EXPECT_EQ(at(x + 8, row2), 255);  // beside the narrower tile: background
  }
  // The label is drawn in the line above each row.
  bool inked = false;
  for (uint32_t y = row1 - Sheet::kTextHeight; y < row1; ++y)
    for (uint32_t x = 0; x < out.width; ++x) inked |= at(x, y) < 128;
  EXPECT_TRUE(inked);
}

namespace {

// A scene of 6 training and 2 test views from the sample scene, each shrunk to 20x20: enough to
// train a few steps and evaluate in seconds.
std::string tinyScene(const test::TempDir& tmp, const std::string& name) {
  const fs::path dir = tmp.path() / name;
  for (const char* split : {"train", "test"}) {
    json j = json::parse(std::ifstream(test::scene() + "/transforms_" + split + ".json"));
    json frames = json::array();
    for (size_t i = 0; i < (std::string(split) == "train" ? 6u : 2u); ++i) {
      json f = j["frames"][i];
      const std::string file = f["file_path"].get<std::string>() + ".png";
      const ImageRGBA8 img = vknerf::downscaleImage(vknerf::loadImage(test::scene() + "/" + file), 5);
      fs::create_directories((dir / file).parent_path());
      vknerf::savePng((dir / file).string(), img);
      frames.push_back(f);
    }
    j["frames"] = frames;
    std::ofstream(dir / (std::string("transforms_") + split + ".json")) << j.dump(1);
  }
  return dir.string();
}

const std::string kTinyTraining =
    " --config vanilla --train-arg=--width=16 --train-arg=--depth=2 --train-arg=--coarse=8 --train-arg=--fine=8"
    " --train-arg=--rays=128 --steps 4";

void expectNoValidationMessages(const fs::path& runs) {
  for (const auto& e : fs::directory_iterator(runs)) {
    if (e.path().extension() != ".log") continue;
    EXPECT_EQ(readText(e.path()).find("vknerf: validation"), std::string::npos) << e.path();
  }
}

}  // namespace

TEST(BenchScenesCli, OneRowPerSceneASheetEachAndABrokenSceneFails) {
  const test::TempDir tmp("bench_scenes");
  const std::string good = tinyScene(tmp, "tiny");
  const fs::path broken = tmp.path() / "broken";
  fs::create_directories(broken);
  std::ofstream(broken / "transforms.json") << "{ not json";
  const fs::path out = tmp.path() / "out";
  auto r = runCli("bench scenes " + good + " " + broken.string() + kTinyTraining + " -o " + out.string());
  EXPECT_EQ(r.code, 1) << r.output;  // the broken scene
  EXPECT_NE(r.output.find("1 of 2 runs failed"), std::string::npos) << r.output;

  const auto rows = csvRows(readText(out / "scenes.csv"));
  ASSERT_EQ(rows.size(), 3u) << r.output;
  EXPECT_EQ(rows[0], csvRows(bench::kSceneTableCsvHeader)[0]);
  ASSERT_EQ(rows[1].size(), 12u);
  EXPECT_EQ(rows[1][0], "tiny");
  EXPECT_EQ(rows[1][11], "ok");
  EXPECT_GT(finite(rows[1][2]), 0.0);                                  // held-out PSNR
  EXPECT_GT(finite(rows[1][3]), 0.0);                                  // SSIM
  EXPECT_LE(finite(rows[1][3]), 1.0);
  EXPECT_EQ(finite(rows[1][4]), 4.0);                                  // steps
  EXPECT_EQ(finite(rows[1][5]), 24.0);  // samples per ray: 8 coarse, then 8 + 8 through the fine network
  EXPECT_GT(finite(rows[1][6]), 0.0);                                  // seconds per view
  EXPECT_EQ(finite(rows[1][7]), 24.0);                                 // a render's samples per pixel: the same
  EXPECT_GT(finite(rows[1][8]), 10.0);                                 // peak host MiB of a Vulkan process
  EXPECT_GT(finite(rows[1][9]), 0.0);                                  // device MiB
  EXPECT_EQ(rows[1][10], "tiny.png");
  ASSERT_EQ(rows[2].size(), 12u);
  EXPECT_EQ(rows[2][0], "broken");
  EXPECT_EQ(rows[2][11].rfind("train failed (exit 1): ", 0), 0u) << rows[2][11];
  EXPECT_NE(rows[2][11].find("transforms.json"), std::string::npos) << rows[2][11];
  for (int c = 2; c <= 7; ++c) EXPECT_EQ(rows[2][c], "") << c;
  const std::string md = readText(out / "scenes.md");
  EXPECT_NE(md.find("| tiny | "), std::string::npos) << md;
  EXPECT_NE(md.find("| broken | "), std::string::npos) << md;

  // The sheet: a title line, then per test view a label line and its 20x20 tiles; the first tile
  // is the view's ground truth (opaque pixels: as the file has them).
  using Sheet = nerf::ContactSheet;
  const ImageRGBA8 sheet = vknerf::loadImage((out / "tiny.png").string());
  EXPECT_EQ(sheet.height, Sheet::kGap + Sheet::kTextHeight + 2 * (Sheet::kTextHeight + 20 + Sheet::kGap));
  EXPECT_GE(sheet.width, Sheet::kGap + 4 * (20 + Sheet::kGap));
  const ImageRGBA8 truth = vknerf::loadImage(good + "/test/r_0.png");
  const uint32_t top = Sheet::kGap + 2 * Sheet::kTextHeight;
  int compared = 0;
  for (uint32_t y = 0; y < 20; ++y)
    for (uint32_t x = 0; x < 20; ++x) {
      const uint8_t* t = &truth.rgba[(size_t(y) * 20 + x) * 4];
      if (t[3] != 255) continue;
      const uint8_t* s = &sheet.rgba[(size_t(top + y) * sheet.width + Sheet::kGap + x) * 4];
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(s[k], t[k], 1) << x << "," << y;
      ++compared;
    }
  EXPECT_GT(compared, 0);
  expectNoValidationMessages(out / "runs");

  // eval --sheet on its own: one view, tiles shrunk to 16 pixels.
  const std::string one = (tmp.path() / "one.png").string();
  auto e = runCli("eval " + (out / "runs" / "tiny.vknerf").string() + " " + good + " --sheet " + one +
                  " --sheet-views 1 --sheet-size 16");
  ASSERT_EQ(e.code, 0) << e.output;
  const ImageRGBA8 small = vknerf::loadImage(one);
  EXPECT_EQ(small.height, Sheet::kGap + Sheet::kTextHeight + Sheet::kTextHeight + 16 + Sheet::kGap);
}

// Two builds in one sitting: a stand-in for an older build whose --help lacks --summary and
// --sheet, so that its steps come from its printed output and its sheet from this build.
TEST(BenchScenesCli, ComparesAnOlderBuildInOneSitting) {
  const test::TempDir tmp("bench_builds");
  const std::string good = tinyScene(tmp, "tiny");
  const fs::path old = tmp.path() / "old" / "vknerf";
  fs::create_directories(old.parent_path());
  std::ofstream(old) << "#!/bin/sh\n"
                        "if [ \"$2\" = --help ]; then \"" VKNERF_BINARY_DIR "/vknerf\" \"$@\" | grep -v -e --summary -e --sheet; exit 0; fi\n"
                        "exec \"" VKNERF_BINARY_DIR "/vknerf\" \"$@\"\n";
  ::chmod(old.c_str(), 0755);
  const fs::path out = tmp.path() / "out";
  auto r = runCli("bench scenes " + good + kTinyTraining + " -o " + out.string() + " --vknerf " + old.string() +
                  " --vknerf now=" VKNERF_BINARY_DIR "/vknerf --sheet-views 1");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto rows = csvRows(readText(out / "scenes.csv"));
  ASSERT_EQ(rows.size(), 3u) << r.output;
  EXPECT_EQ(rows[1][1], "old");
  EXPECT_EQ(rows[2][1], "now");
  for (int i : {1, 2}) {
    EXPECT_EQ(rows[i][11], "ok");
    EXPECT_EQ(finite(rows[i][4]), 4.0);
    EXPECT_EQ(finite(rows[i][5]), 24.0);
    EXPECT_GT(finite(rows[i][9]), 0.0);
    EXPECT_EQ(rows[i][10], "tiny-" + rows[i][1] + ".png");
    // One view of the two, as --sheet-views asked, on the older build's sheet too (this build drew it).
    using Sheet = nerf::ContactSheet;
    EXPECT_EQ(vknerf::loadImage((out / rows[i][10]).string()).height, Sheet::kGap + 2 * Sheet::kTextHeight + 20 + Sheet::kGap);
  }
  EXPECT_FALSE(fs::exists(out / "runs" / "tiny-old.train.json"));  // no --summary: read from its output
  EXPECT_TRUE(fs::exists(out / "runs" / "tiny-now.train.json"));
  expectNoValidationMessages(out / "runs");
}

TEST(BenchScenesCli, BadInputIsOneLineBeforeAnyWork) {
  const test::TempDir tmp("bench_bad");
  const std::string scene = test::scene(), out = " -o " + tmp.file("out");
  struct Case {
    std::string args;
    int code;
    std::string fragment;
  };
  for (const Case& c : std::vector<Case>{
           {scene + out, 2, "--time S or --steps N"},
           {"/no/such/scene --steps 1" + out, 1, "/no/such/scene"},
           {scene + " --steps 1 -o /dev/null/x", 1, "/dev/null/x"},
           {scene + " --steps 1" + out + " --vknerf /no/such/vknerf", 1, "/no/such/vknerf"},
           {"--vknerf /no/such/vknerf " + scene + " --steps 1" + out, 1, "/no/such/vknerf"},  // a scene, not a build
           {scene + " " + scene + " --steps 1" + out, 2, "two scenes are named tabletop"},
           {scene + " --steps 1" + out + " --no-such-flag", 2, "--no-such-flag"},
       }) {
    auto r = runCli("bench scenes " + c.args);
    EXPECT_EQ(r.code, c.code) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.fragment), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_EQ(r.output.find("training"), std::string::npos) << r.output;
  }
}

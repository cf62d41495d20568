// Bad input at the front door: each case is a flag, a mutation of a copy of the sample scene, a
// crafted checkpoint or an output that cannot be written, with the exit code and a fragment of the
// one-line message it must give (0 ok, 1 runtime error, 2 usage error). Nothing may crash, hang,
// train before failing, or report success after a failed write.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "support/cli_run.h"
#include "io/checkpoint.h"

namespace fs = std::filesystem;
using nlohmann::json;
using vknerf::test::runCli;
using vknerf::test::scene;
using vknerf::test::temp;

namespace {

struct Case {
  std::string name, args;
  int code;
  std::string fragment;
  std::string absent = "  loss ";  // a failure found up front prints no training progress
};

void runCases(const std::vector<Case>& cases) {
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name + ": vknerf " + c.args);
    auto r = runCli(c.args);
    EXPECT_EQ(r.code, c.code) << r.output;
    EXPECT_NE(r.output.find(c.fragment), std::string::npos) << "expected '" << c.fragment << "' in:\n" << r.output;
    if (!c.absent.empty()) EXPECT_EQ(r.output.find(c.absent), std::string::npos) << r.output;
  }
}

const std::string kTiny = " --downscale 4 --width 16 --depth 2 --coarse 8 --fine 8 --rays 128";

// A copy of the sample scene with `mutate` applied to one of its transforms files.
std::string mutatedScene(const std::string& name, const std::string& file, const std::function<void(json&)>& mutate) {
  const fs::path dir = temp("scene_" + name);
  fs::remove_all(dir);
  fs::copy(scene(), dir, fs::copy_options::recursive);
  json j = json::parse(std::ifstream(dir / file));
  mutate(j);
  std::ofstream(dir / file) << j.dump(2);
  return dir.string();
}

// A tiny model of the sample scene (2 steps), trained once per test process.
const std::string& tinyModel() {
  static const std::string path = [] {
    const std::string p = temp("tiny.vknerf");
    auto r = runCli("train " + scene() + " -o " + p + kTiny + " --steps 2");
    EXPECT_EQ(r.code, 0) << r.output;
    return p;
  }();
  return path;
}

// A copy of the tiny model with its config or parameters changed and the checksum recomputed.
std::string craftedCheckpoint(const std::string& name, const std::function<void(vknerf::nerf::Checkpoint&)>& change) {
  auto ck = vknerf::nerf::Checkpoint::load(tinyModel());
  change(ck);
  const std::string path = temp(name + ".vknerf");
  ck.save(path);
  return path;
}

void editConfig(vknerf::nerf::Checkpoint& ck, const std::function<void(json&)>& edit) {
  json j = json::parse(ck.config);
  edit(j["config"]);
  ck.config = j.dump(2);
}

}  // namespace

TEST(BadInput, FlagsAreUsageErrors) {
  const std::string out = " -o " + temp("flags.vknerf");
  runCases({
      {"unknown command", "frobnicate", 2, "unknown command 'frobnicate' (commands: "},
      {"NaN time", "train " + scene() + out + " --time nan", 2, "must be a positive finite number, got nan"},
      {"zero time without a 309-digit bound", "train " + scene() + out + " --time 0", 2,
       "--time: must be a positive finite number, got 0"},
      {"width not a multiple of 8", "train " + scene() + out + " --steps 1 --width 12", 2,
       "model.width must be a multiple of 8, got 12"},
      {"NaN orbit radius", "render no.vknerf --orbit 1 --size 16 --radius nan -o " + temp("r"), 2,
       "must be a finite number, got nan"},
      {"fit-image width", "fit-image " + scene() + "/train/r_0.png --width 6 --steps 1", 2, "multiple of 4"},
  });
}

// A batch whose rays do not fit one binding is refused with the largest batch that does, before
// anything is allocated or trained (2^24 rays of 32 bytes is 512 MiB; every device here binds
// 128 MiB: lavapipe's limit, the minimum the spec requires is lower still).
TEST(BadInput, BatchesOverTheBindingLimitSayTheLargestThatFits) {
  const std::string out = " -o " + temp("huge.vknerf") + " --steps 1";
  for (const char* config : {"vanilla", "fast"}) {
    SCOPED_TRACE(config);
    auto r = runCli("train " + scene() + out + " --config " + config + " --rays 16777216");
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find(" rays per batch"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("a batch of 16777216 rays needs 536870912 bytes"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("  loss "), std::string::npos) << r.output;
  }
}

TEST(BadInput, OutputsAreCheckedBeforeWorkAndWritesAreChecked) {
  const std::string folder = temp("an_output_folder");
  fs::create_directories(folder);
  const std::string copy = mutatedScene("outputs", "transforms_train.json", [](json&) {});
  runCases({
      {"model into a missing folder", "train " + scene() + " --time 8 -o /no/such/dir/m.vknerf" + kTiny, 1,
       "folder /no/such/dir does not exist"},
      {"model onto a folder", "train " + scene() + " --steps 1 -o " + folder + kTiny, 1, "is a folder"},
      {"model onto the dataset", "train " + copy + " --steps 1 -o " + copy + "/transforms_train.json" + kTiny, 2,
       "is one of the files of the scene " + copy},
      {"eval JSON into a missing folder", "eval " + tinyModel() + " " + scene() + " --json /no/such/dir/r.json", 1,
       "folder /no/such/dir does not exist"},
      {"eval JSON and CSV on a full device",
       "eval " + tinyModel() + " " + scene() + " --downscale 4 --limit 1 --json /dev/full --csv /dev/full", 1,
       "/dev/full: write failed"},
      {"render into a file", "render " + tinyModel() + " --orbit 1 --size 8 -o /dev/full", 1, "output folder /dev/full: "},
      {"fit-image onto a full device", "fit-image " + scene() + "/train/r_0.png --steps 1 --every 0 -o /dev/full", 1,
       "/dev/full: write failed"},
  });
  // The dataset file is untouched.
  EXPECT_NO_THROW(json::parse(std::ifstream(copy + "/transforms_train.json")));
}

TEST(BadInput, SceneValuesBeyondTheDeviceFloatRange) {
  const auto frame0 = [](double v, int row, int col) {
    return [=](json& j) { j["frames"][0]["transform_matrix"][row][col] = v; };
  };
  const std::string far = mutatedScene("far_test_camera", "transforms_test.json", frame0(1e39, 0, 3));
  const std::string huge = mutatedScene("huge_translation", "transforms_train.json", frame0(1e308, 1, 3));
  const std::string narrow = mutatedScene("narrow_angle", "transforms_train.json",
                                          [](json& j) { j["camera_angle_x"] = 1e-300; });
  const std::string cx = mutatedScene("far_cx", "transforms_train.json", [](json& j) { j["cx"] = 1e300; });
  const std::string out = " -o " + temp("floats.vknerf") + kTiny + " --steps 1";
  runCases({
      {"test camera at 1e39 (once a crash in the depth writer)",
       "render " + tinyModel() + " " + far + " --downscale 4 --limit 1 -o " + temp("far_render"), 1,
       "transforms_test.json: frames[0]: transform_matrix value 1e+39 is beyond the range"},
      {"translation 1e308", "train " + huge + out, 1, "transform_matrix value 1e+308 is beyond the range"},
      {"camera_angle_x 1e-300", "train " + narrow + out, 1, "camera_angle_x"},
      {"cx 1e300", "train " + cx + out, 1, "principal point cx value 1e+300"},
  });
}

TEST(BadInput, CheckpointsAreCheckedBeyondTheirChecksum) {
  const std::string noSamples = craftedCheckpoint(
      "no_samples", [](auto& ck) { editConfig(ck, [](json& c) { c["model"]["coarse_samples"] = 0; }); });
  const std::string badActivation = craftedCheckpoint(
      "bad_activation", [](auto& ck) { editConfig(ck, [](json& c) { c["model"]["density"] = 7; }); });
  const std::string nanWeights = craftedCheckpoint("nan_weights", [](auto& ck) {
    auto& bytes = ck.sections.at("coarse.params");
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(bytes.data(), &nan, 4);
  });
  const std::string folder = temp("checkpoint_folder");
  fs::create_directories(folder);
  const std::string render = " --orbit 1 --size 8 -o " + temp("ck_render");
  const std::string resumed = temp("resumed.vknerf");
  fs::copy_file(tinyModel(), resumed, fs::copy_options::overwrite_existing);
  const std::string otherBox = mutatedScene("other_box", "transforms_train.json",
                                            [](json& j) { j["aabb"] = {{-2, -2, -1}, {2, 2, 1}}; });
  const std::string resume = " -o " + resumed + " --resume --downscale 4";
  runCases({
      {"coarse_samples 0", "render " + noSamples + render, 1, "model.coarse_samples must be in [1, 4096], got 0"},
      {"unknown activation", "render " + badActivation + render, 1, "model.density is not a known activation"},
      {"NaN weights", "render " + nanWeights + render, 1, "holds a non-finite value"},
      {"checkpoint is a folder", "eval " + folder + " " + scene(), 1, folder + ": is a folder, not a checkpoint"},
      {"steps past the counter", "train " + scene() + resume + " --steps 4294967295", 2,
       "passes the step counter's limit"},
      {"flag conflicting with the checkpoint", "train " + scene() + resume + " --steps 1 --width 32", 2,
       "--width 32 conflicts with " + resumed + "'s model/width 16"},
      {"resume on another scene box", "train " + otherBox + resume + " --steps 1", 1, "checkpoint scene box"},
      {"resume at another image size", "train " + scene() + " -o " + resumed + " --resume --downscale 2 --steps 1", 1,
       "it was trained on another scene or --downscale"},
  });
}

// Bad input at the front door: each case is a flag, a mutation of a copy of the sample scene, a
// crafted checkpoint or an output that cannot be written, with the exit code and a fragment of the
// one-line message it must give (0 ok, 1 runtime error, 2 usage error). Nothing may crash, hang,
// train before failing, or report success after a failed write.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <stb/stb_image_write.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

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
#include "io/checkpoint/checkpoint.h"
#include "vknerf/image_io.h"

namespace fs = std::filesystem;
using nlohmann::json;
using vknerf::test::runCli;
using vknerf::test::scene;
using vknerf::test::shellWaitUntil;
using vknerf::test::temp;

namespace {

struct Case {
  std::string name, args;
  int code;
  std::string fragment;
  std::string absent = "  loss ";  // a failure found up front prints no training progress
  std::string env = "";            // variables set for the command ("PATH=...")
};

void runCases(const std::vector<Case>& cases) {
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name + ": vknerf " + c.args);
    auto r = runCli(c.args, c.env);
    EXPECT_EQ(r.code, c.code) << r.output;
    EXPECT_NE(r.output.find(c.fragment), std::string::npos) << "expected '" << c.fragment << "' in:\n" << r.output;
    if (!c.absent.empty()) EXPECT_EQ(r.output.find(c.absent), std::string::npos) << r.output;
  }
}

// The smallest vanilla model (its --coarse/--fine are vanilla's flags): cheap to train, and the
// crafted checkpoints below edit its vanilla sections.
const std::string kTiny = " --config vanilla --downscale 4 --width 16 --depth 2 --coarse 8 --fine 8 --rays 128";

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

// A tiny vanilla model of the sample scene (2 steps), trained once per test process.
const std::string& tinyModel() {
  static const std::string path = [] {
    const std::string p = temp("tiny.vknerf");
    auto r = runCli("train " + scene() + " -o " + p + kTiny + " --steps 2");
    EXPECT_EQ(r.code, 0) << r.output;
    return p;
  }();
  return path;
}

// A tiny fast model with camera refinement and an appearance embedding (1 step), trained once per
// test process.
const std::string& tinyRefinedModel() {
  static const std::string path = [] {
    const std::string p = temp("tiny_refined.vknerf");
    auto r = runCli("train " + scene() + " -o " + p + " --config fast --refine-cameras --appearance-dims 4 --downscale 4 "
                    "--rays 128 --hash-levels 2 --grid 16 --steps 1");
    EXPECT_EQ(r.code, 0) << r.output;
    return p;
  }();
  return path;
}

// A copy of the tiny model with its config or parameters changed and the checksum recomputed.
std::string craftedCheckpoint(const std::string& name, const std::function<void(vknerf::io::Checkpoint&)>& change,
                              const std::string& from = "") {
  auto ck = vknerf::io::Checkpoint::load(from.empty() ? tinyModel() : from);
  change(ck);
  const std::string path = temp(name + ".vknerf");
  ck.save(path);
  return path;
}

void editConfig(vknerf::io::Checkpoint& ck, const std::function<void(json&)>& edit) {
  json j = json::parse(ck.config);
  edit(j["config"]);
  ck.config = j.dump(2);
}

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A nerfstudio camera path of one 8x8 frame at `fov` degrees, looking at the origin from +z.
std::string cameraPath(const std::string& name, double fov) {
  const std::string path = temp(name + ".json");
  const json pose = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 4, 0, 0, 0, 1};
  std::ofstream(path) << json{{"render_width", 8}, {"render_height", 8}, {"fps", 24},
                              {"camera_path", {{{"camera_to_world", pose}, {"fov", fov}}}}}
                             .dump();
  return path;
}

// A folder of the sample scene's first `n` training photos, as PNG files p0.png, ...
std::string photoFolder(const std::string& name, int n) {
  const fs::path dir = temp(name);
  fs::create_directories(dir);
  for (int i = 0; i < n; ++i)
    fs::copy_file(scene() + "/train/r_" + std::to_string(i) + ".png", dir / ("p" + std::to_string(i) + ".png"),
                  fs::copy_options::overwrite_existing);
  return dir.string();
}

bool haveFfmpeg() { return std::system("command -v ffmpeg > /dev/null 2>&1") == 0; }

// The files in `dir` whose names hold `part`.
std::vector<std::string> namesWith(const std::string& dir, const std::string& part) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().find(part) != std::string::npos) out.push_back(e.path().string());
  return out;
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
      {"NaN min transmittance", "render no.vknerf --orbit 1 --size 16 --min-transmittance nan -o " + temp("r"), 2,
       "--min-transmittance: must be a number in [0, 1), got nan"},
      {"min transmittance 1", "eval no.vknerf " + scene() + " --min-transmittance 1", 2,
       "--min-transmittance: must be a number in [0, 1), got 1"},
      // A vanilla model's rays take a fixed count of samples: the cut would change nothing.
      {"min transmittance on a vanilla render", "render " + tinyModel() + " --orbit 1 --size 8 --min-transmittance 0.01 -o " +
       temp("r_vanilla"), 2, "render: --min-transmittance has no effect on " + tinyModel() + ", a vanilla model"},
      {"min transmittance on a vanilla eval", "eval " + tinyModel() + " " + scene() + " --min-transmittance 0.01", 2,
       "eval: --min-transmittance has no effect on " + tinyModel() + ", a vanilla model"},
      // Only a proposal places a chosen count of samples: a vanilla model's rays have their own.
      {"proposal samples on a vanilla render", "render " + tinyModel() + " --orbit 1 --size 8 --proposal-samples 8 -o " +
       temp("r_vanilla_samples"), 2, "render: --proposal-samples has no effect on " + tinyModel() +
       ", whose rays are not sampled by a proposal"},
      {"zero proposal samples", "eval no.vknerf " + scene() + " --proposal-samples 0", 2, "--proposal-samples: "},
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
  EXPECT_TRUE(json::accept(std::ifstream(copy + "/transforms_train.json")));
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
      {"appearance of a model without one", "render " + tinyModel() + render + " --appearance 0", 1,
       "the model has no appearance embedding (model.appearance_dims is 0)"},
      {"steps past the counter", "train " + scene() + resume + " --steps 4294967295", 2,
       "passes the step counter's limit"},
      {"flag conflicting with the checkpoint", "train " + scene() + resume + " --steps 1 --width 32", 2,
       "--width 32 conflicts with " + resumed + "'s model/width 16"},
      {"resume on another scene box", "train " + otherBox + resume + " --steps 1", 1, "checkpoint scene box"},
      {"resume at another image size", "train " + scene() + " -o " + resumed + " --resume --downscale 2 --steps 1", 1,
       "it was trained on another scene or --downscale"},
  });
}

// A camera record is checked for what training can write, not only for finite numbers: a
// correction within reach of the box, a recorded pose rigid. One line naming the field.
TEST(BadInput, CameraRecordsAreCheckedForWhatTrainingWrites) {
  const auto correction = [](const std::string& name, size_t index, float value) {
    return craftedCheckpoint(name, [=](auto& ck) {
      auto& bytes = ck.sections.at("cameras.params");
      std::memcpy(bytes.data() + 4 * index, &value, 4);
    }, tinyRefinedModel());
  };
  const std::string turned = correction("turned_camera", 1, 1e30f), shifted = correction("shifted_camera", 6 + 4, 1e30f);
  const std::string scaled = craftedCheckpoint("scaled_pose", [](auto& ck) {
    json j = json::parse(ck.config);
    for (int i : {0, 5, 10}) j["training_cameras"][0]["c2w"][i] = j["training_cameras"][0]["c2w"][i].template get<double>() * 2;
    ck.config = j.dump(2);
  });
  // Rendering uses neither (the views are the scene's or the orbit's): resuming and exporting do.
  const std::string far = craftedCheckpoint("far_pose", [](auto& ck) {
    json j = json::parse(ck.config);
    j["training_cameras"][1]["c2w"][3] = 1e20;
    ck.config = j.dump(2);
  });
  const std::string resumed = temp("turned_resumed.vknerf");
  fs::copy_file(turned, resumed, fs::copy_options::overwrite_existing);
  const std::string before = bytesOf(resumed), shiftedBefore = bytesOf(shifted);
  runCases({
      {"rotation correction 1e30, resumed", "train " + scene() + " -o " + resumed + " --resume --downscale 4 --steps 1", 1,
       resumed + ": checkpoint section 'cameras.params': camera 0's rotation correction (w) turns 1e+30 radians"},
      {"translation correction 1e30, resumed", "train " + scene() + " -o " + shifted + " --resume --downscale 4 --steps 1", 1,
       "camera 1's translation correction (tau) is 1e+30 long, beyond 10 times the scene box's side"},
      {"a recorded pose scaled", "export cameras " + scaled + " -o " + temp("scaled.json"), 1,
       scaled + ": checkpoint training_cameras[0]: c2w rotation part is not orthonormal"},
      {"a recorded camera 1e20 away", "export cameras " + far + " -o " + temp("far.json"), 1,
       far + ": checkpoint training_cameras[1]: c2w value 1e+20 is beyond the range the device computes with"},
  });
  EXPECT_EQ(bytesOf(resumed), before);
  EXPECT_EQ(bytesOf(shifted), shiftedBefore);
  EXPECT_FALSE(fs::exists(temp("scaled.json")));
  EXPECT_FALSE(fs::exists(temp("far.json")));
}

// An output is never an input, nor another output: by path, symlink or hard link, and a folder
// output never holds or lies in an input folder. Each is a usage error naming both, before any work.
TEST(BadInput, AnOutputNeverReplacesAnInput) {
  const std::string model = temp("victim.vknerf"), link = temp("victim_link.vknerf"), hard = temp("victim_hard.vknerf");
  fs::copy_file(tinyModel(), model, fs::copy_options::overwrite_existing);
  fs::create_symlink(model, link);
  fs::create_hard_link(model, hard);
  const std::string before = bytesOf(model);
  const std::string path = cameraPath("victim_path", 50), photos = photoFolder("victim_photos", 3);
  const std::string report = temp("report.txt"), copy = mutatedScene("victim_scene", "transforms_train.json", [](json&) {});
  runCases({
      {"mesh over the model", "export mesh " + model + " -o " + model, 2,
       "export mesh: -o " + model + " would replace the model " + model + " (the same file)"},
      {"mesh over a symlink to the model", "export mesh " + model + " -o " + link, 2,
       "-o " + link + " would replace the model " + model},
      {"mesh over a hard link of the model", "export mesh " + model + " -o " + hard, 2,
       "-o " + hard + " would replace the model " + model},
      {"points over the model", "export points " + model + " --scene " + scene() + " -o " + model, 2,
       "would replace the model " + model},
      {"cameras over a symlink to the model", "export cameras " + model + " -o " + link, 2,
       "export cameras: -o " + link + " would replace the model " + model},
      {"eval JSON over the model", "eval " + model + " " + scene() + " --json " + model, 2,
       "--json " + model + " would replace the model " + model},
      {"video over the model", "render " + model + " --path " + path + " --video " + model, 2,
       "--video " + model + " would replace the model " + model},
      {"JSON and CSV into one file", "eval " + model + " " + scene() + " --json " + report + " --csv " + report, 2,
       "--json " + report + " would replace --csv " + report + " (the same file); give each output its own path"},
      {"scene over the photos", "process " + photos + " -o " + photos + "/", 2,
       "-o " + photos + "/ would replace the input " + photos + " (the same folder)"},
      {"scene inside the photos", "process " + photos + " -o " + photos + "/scene", 2, "lies inside the input " + photos},
      {"scene around the photos", "process " + photos + " -o " + fs::path(photos).parent_path().string(), 2,
       "holds the input " + photos},
      {"frames into the scene", "render " + model + " " + copy + " -o " + copy + "/renders", 2,
       "output folder " + copy + "/renders lies inside the scene " + copy},
  });
  EXPECT_EQ(bytesOf(model), before);
  EXPECT_EQ(namesWith(photos, ".png").size(), 3u);
  EXPECT_FALSE(fs::exists(copy + "/renders"));
  EXPECT_FALSE(fs::exists(report));
}

// A scene's own files are never an output, whether or not the command was given the scene: every
// format's files (transforms, COLMAP's model, poses_bounds.npy, photos in images/ and images_<n>/)
// and a new split. Each is a usage error naming the file, and the file is left as it was.
TEST(BadInput, SceneFilesAreNeverOutputs) {
  const std::string model = tinyModel();
  const std::string blender = mutatedScene("own_files", "transforms_train.json", [](json&) {});
  // Another scene, known by its transforms.json only.
  const fs::path other = temp("other_scene");
  fs::create_directories(other);
  std::ofstream(other / "transforms.json") << "{\"frames\": []}";
  // A COLMAP text model in sparse/0/ beside images/, and an LLFF scene with its downscaled photos.
  const fs::path colmap = temp("colmap_scene"), llff = temp("llff_scene");
  fs::create_directories(colmap / "sparse" / "0");
  fs::create_directories(colmap / "images");
  for (const char* f : {"cameras.txt", "images.txt", "points3D.txt"}) std::ofstream(colmap / "sparse" / "0" / f) << "# model\n";
  fs::create_directories(llff / "images");
  fs::create_directories(llff / "images_4");
  std::ofstream(llff / "poses_bounds.npy") << "not really a numpy file";
  const std::vector<fs::path> kept = {fs::path(blender) / "transforms_train.json", fs::path(blender) / "transforms_test.json",
                                      other / "transforms.json", colmap / "sparse" / "0" / "images.txt",
                                      llff / "poses_bounds.npy"};
  std::vector<std::string> before;
  for (const fs::path& f : kept) before.push_back(bytesOf(f.string()));
  const std::string cameras = "export cameras " + model + " -o ", npy = (llff / "poses_bounds.npy").string();
  const std::string evalArgs = "eval " + model + " " + scene() + " --downscale 4 --limit 1 ";
  const std::string fit = "fit-image " + scene() + "/train/r_0.png --steps 1 --every 0 -o ";
  const auto own = [](const std::string& flag, const std::string& file) { return flag + " " + file + " is one of the files of the scene "; };
  runCases({
      {"cameras over the training poses", cameras + blender + "/transforms_train.json", 2,
       own("-o", blender + "/transforms_train.json") + blender},
      {"cameras over the test poses", cameras + blender + "/transforms_test.json", 2, own("-o", blender + "/transforms_test.json")},
      {"cameras as a new split", cameras + blender + "/transforms_val.json", 2, own("-o", blender + "/transforms_val.json")},
      {"cameras over another scene's poses", cameras + (other / "transforms.json").string(), 2,
       own("-o", (other / "transforms.json").string())},
      {"cameras over a COLMAP model", cameras + (colmap / "sparse" / "0" / "images.txt").string(), 2,
       own("-o", (colmap / "sparse" / "0" / "images.txt").string())},
      {"cameras over poses_bounds.npy", cameras + npy, 2, own("-o", npy)},
      {"train summary over poses_bounds.npy", "train " + scene() + " -o " + temp("own.vknerf") + kTiny + " --steps 1 --summary " + npy,
       2, own("--summary", npy)},
      {"eval sheet over poses_bounds.npy", evalArgs + "--sheet " + npy, 2, own("--sheet", npy), "PSNR"},
      {"eval JSON over poses_bounds.npy", evalArgs + "--json " + npy, 2, own("--json", npy), "PSNR"},
      {"an image into LLFF's downscaled photos", fit + (llff / "images_4" / "new.png").string(), 2,
       own("-o", (llff / "images_4" / "new.png").string())},
      {"an image into COLMAP's photos", fit + (colmap / "images" / "new.png").string(), 2,
       own("-o", (colmap / "images" / "new.png").string())},
      {"frames into LLFF's photos", "render " + model + " --orbit 1 --size 8 -o " + (llff / "images_4").string(), 2,
       "output folder " + (llff / "images_4").string() + " lies in the photos or model of the scene "},
      {"a processed scene as LLFF's photos", "process " + photoFolder("photos_into_llff", 3) + " -o " + (llff / "images_4").string(),
       2, "-o " + (llff / "images_4").string() + " lies in the photos or model of the scene ", "colmap"},
  });
  for (size_t i = 0; i < kept.size(); ++i) EXPECT_EQ(bytesOf(kept[i].string()), before[i]) << kept[i];
  EXPECT_FALSE(fs::exists(fs::path(blender) / "transforms_val.json"));
  EXPECT_FALSE(fs::exists(llff / "images_4" / "new.png"));
  EXPECT_FALSE(fs::exists(colmap / "images" / "new.png"));
  EXPECT_TRUE(fs::is_empty(llff / "images_4"));
}

// A value the loader would clamp, and a flag that would do nothing, are refused rather than
// silently changed or ignored.
TEST(BadInput, ClampsAndFlagsWithoutEffectAreRefused) {
  // instant-ngp's cube in both splits (the box is the first file's that states one).
  const auto cube = [](const std::string& name, double side) {
    const auto toCube = [side](json& j) {
      j.erase("aabb");
      j["aabb_scale"] = side;
    };
    const std::string dir = mutatedScene(name, "transforms_train.json", toCube);
    json test = json::parse(std::ifstream(dir + "/transforms_test.json"));
    toCube(test);
    std::ofstream(dir + "/transforms_test.json") << test.dump(2);
    return dir;
  };
  const std::string out = " -o " + temp("clamps.vknerf") + " --steps 1";
  const std::string fast = " --config fast --downscale 4";
  const std::string evalArgs = "eval " + tinyModel() + " " + scene() + " --downscale 4 --limit 1";
  runCases({
      {"aabb_scale 256", "train " + cube("cube_256", 256) + out + kTiny, 1,
       "transforms_train.json: field 'aabb_scale' must be at most 128 (instant-ngp's largest cube), got 256"},
      {"aabb_scale 1e9", "train " + cube("cube_1e9", 1e9) + out + kTiny, 1, "field 'aabb_scale' must be at most 128"},
      {"aabb_scale 128 trains", "train " + cube("cube_128", 128) + out + kTiny, 0, "done after 1 steps", ""},
      {"--camera-lr without --refine-cameras", "train " + scene() + out + fast + " --camera-lr 0.01", 2,
       "train: --camera-lr has no effect without --refine-cameras"},
      {"--camera-penalty without --refine-cameras", "train " + scene() + out + fast + " --camera-penalty 1", 2,
       "train: --camera-penalty has no effect without --refine-cameras"},
      {"--proposal-stride with the march", "train " + scene() + out + fast + " --proposal-samples 0 --proposal-stride 4", 2,
       "train: --proposal-stride has no effect with --proposal-samples 0"},
      {"--proposal-anneal-steps with the march",
       "train " + scene() + out + fast + " --proposal-samples 0 --proposal-anneal-steps 100", 2,
       "train: --proposal-anneal-steps has no effect with --proposal-samples 0"},
      {"--proposal-levels with the march", "train " + scene() + out + fast + " --proposal-samples 0 --proposal-levels 3", 2,
       "train: --proposal-levels has no effect with --proposal-samples 0"},
      {"--profile-steps without --profile", "train " + scene() + out + kTiny + " --profile-steps 4", 2,
       "train: --profile-steps has no effect without --profile"},
      {"--sheet-views without --sheet", evalArgs + " --sheet-views 2", 2, "eval: --sheet-views has no effect without --sheet", "PSNR"},
      {"--sheet-size without --sheet", evalArgs + " --sheet-size 64", 2, "eval: --sheet-size has no effect without --sheet", "PSNR"},
      {"--elevation without --orbit", "render " + tinyModel() + " " + scene() + " --elevation 30 -o " + temp("no_render"), 2,
       "render: --elevation has no effect without --orbit"},
      {"--size with a SCENE", "render " + tinyModel() + " " + scene() + " --size 64 -o " + temp("no_render"), 2,
       "render: --size has no effect"},
      {"--split with --orbit", "render " + tinyModel() + " --orbit 1 --split train -o " + temp("no_render"), 2,
       "render: --split has no effect"},
      {"--downscale without a SCENE", "render " + tinyModel() + " --orbit 1 --downscale 2 -o " + temp("no_render"), 2,
       "render: --downscale has no effect"},
      {"--fps without a video", "render " + tinyModel() + " --orbit 1 --fps 30 -o " + temp("no_render"), 2,
       "render: --fps has no effect without --video"},
      {"--width without a path", "render " + tinyModel() + " --orbit 1 --width 64 -o " + temp("no_render"), 2,
       "render: --width has no effect without an instant-ngp --path"},
      {"process --fps on photos", "process " + photoFolder("fps_photos", 3) + " --fps 4 -o " + temp("no_scene"), 2,
       "process: --fps has no effect on a folder of photos", "colmap"},
  });
  EXPECT_FALSE(fs::exists(temp("no_scene")));
  EXPECT_FALSE(fs::exists(temp("no_render")));
}

// The video goes through the writer every output does: into a pipe or a device in place (not renamed
// over it), and no temporary file or log is left when a signal ends the render; a good video stays.
TEST(BadInput, VideoIsWrittenAsEveryOtherOutput) {
  if (!haveFfmpeg()) GTEST_SKIP() << "ffmpeg is not installed";
  const std::string dir = temp("video");
  fs::create_directories(dir);
  const std::string model = tinyModel(), orbit = "render " + model + " --orbit 2 --size 8 --video ";
  const std::string fifo = dir + "/pipe", received = dir + "/received.mp4";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // The reader gives up after a while, so a render that fails before opening the pipe cannot hang the test.
  auto r = runCli(orbit + fifo + " 2>&1 & pid=$!; timeout 300 cat " + fifo + " > " + received + "; wait $pid");
  EXPECT_EQ(r.code, 0) << r.output;
  struct stat st;
  ASSERT_EQ(::stat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the pipe was replaced";
  EXPECT_EQ(bytesOf(received).substr(4, 4), "ftyp") << "the pipe's reader got no MP4";
  // Copies of /dev/null and /dev/full (root may make device nodes; others skip these two).
  const std::string null = dir + "/null", full = dir + "/full";
  if (::mknod(null.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0 && ::mknod(full.c_str(), S_IFCHR | 0666, makedev(1, 7)) == 0) {
    runCases({{"video into a null device", orbit + null, 0, "wrote " + null},
              {"video into a full device", orbit + full, 1, full + ": write failed: No space left on device"}});
    for (const std::string& device : {null, full}) {
      ASSERT_EQ(::stat(device.c_str(), &st), 0);
      EXPECT_TRUE(S_ISCHR(st.st_mode)) << device << " was replaced";
    }
  }
  EXPECT_EQ(namesWith(dir, ".tmp."), std::vector<std::string>{});
  for (const char* special : {"vknerf-pipe.tmp.", "vknerf-null.tmp.", "vknerf-full.tmp."})
    EXPECT_EQ(namesWith(fs::temp_directory_path().string(), special), std::vector<std::string>{});
  // A signal while ffmpeg encodes (its temporary files exist): the exit status of the signal, the
  // earlier video untouched, nothing left beside it.
  for (const auto& [signal, code] : {std::pair<std::string, int>{"TERM", 143}, {"INT", 130}}) {
    SCOPED_TRACE(signal);
    const std::string video = dir + "/good.mp4";
    std::ofstream(video) << "a good video";
    r = runCli("render " + model + " --orbit 10000 --size 32 --video " + video + " 2>&1 & pid=$!; " +
               "for i in $(seq 600); do ls " + dir + "/good.mp4.tmp.* > /dev/null 2>&1 && break; sleep 0.1; done; " +
               "kill -" + signal + " $pid; wait $pid");
    EXPECT_EQ(r.code, code) << r.output;
    EXPECT_EQ(bytesOf(video), "a good video");
    EXPECT_EQ(namesWith(dir, ".tmp."), std::vector<std::string>{});
  }
}

// Every input is read and checked before any output or folder is made; an input that does not fit
// the others (another scene's cameras for a model, one photo with two poses) is refused.
TEST(BadInput, InputsAreCheckedBeforeAnyOutputIsMade) {
  const std::string model = tinyModel(), out = temp("never_made");
  const std::string badPath = temp("bad_path.json");
  std::ofstream(badPath) << "{\"camera_path\": [";
  const std::string otherBox = mutatedScene("points_other_box", "transforms_train.json",
                                            [](json& j) { j["aabb"] = {{-2, -2, -1}, {2, 2, 1}}; });
  const std::string fewer = mutatedScene("points_fewer_cameras", "transforms_train.json",
                                         [](json& j) { j["frames"].erase(j["frames"].size() - 1); });
  const std::string twice = mutatedScene("one_photo_two_poses", "transforms_train.json", [](json& j) {
    j["frames"][1]["file_path"] = j["frames"][0]["file_path"];
  });
  std::vector<Case> cases = {
      {"render with a missing model", "render " + temp("missing.vknerf") + " --orbit 1 --size 8 -o " + out, 1,
       "missing.vknerf: cannot open checkpoint"},
      {"render with a broken path", "render " + model + " --path " + badPath + " -o " + out, 1,
       badPath + ": invalid JSON"},
      {"render with a missing scene", "render " + model + " " + temp("no_scene") + " -o " + out, 1, "does not exist"},
      {"points of a scene with another box", "export points " + model + " --scene " + otherBox + " --downscale 4 -o " +
       temp("p.ply"), 1, model + ": checkpoint scene box [-1.1 -1.1 -0.55]..[1.1 1.1 0.75] differs from this dataset's"},
      {"points of a scene with other cameras", "export points " + model + " --scene " + fewer + " --downscale 4 -o " +
       temp("p.ply"), 1, "trained on 100 images, this dataset's training split has 99"},
      {"one photo listed twice with two poses", "train " + twice + " -o " + temp("twice.vknerf") + kTiny + " --steps 1",
       1, "transforms_train.json: frames[1]: image '" + twice + "/./train/r_0.png' is listed again with another pose than at "},
  };
  // Root may write anywhere but /proc takes no new file either way: found before the evaluation.
  if (fs::is_directory("/proc"))
    cases.push_back({"eval JSON where no file can be made", "eval " + model + " " + scene() + " --json /proc/vknerf.json",
                     1, "--json /proc/vknerf.json: cannot write", "PSNR"});
  runCases(cases);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(temp("p.ply")));
}

// One line naming the file and the field, in that format's own words; COLMAP's failures in one line
// with the stage and the log; the flags where 0 means "all" say so; a threshold no density reaches
// is refused rather than meshed into nothing.
TEST(BadInput, MessagesNameTheFileAndTheField) {
  const std::string model = tinyModel(), folder = temp("a_folder");
  fs::create_directories(folder);
  const std::string narrow = cameraPath("narrow_path", 1e-30);
  // Photos vknerf cannot decode: a text file named .jpg and a JPEG cut short.
  const std::string broken = photoFolder("broken_photos", 3);
  std::ofstream(broken + "/notes.jpg") << "not a photo";
  std::vector<uint8_t> rgb(16 * 16 * 3, 128), jpeg;
  stbi_write_jpg_to_func([](void* out, void* data, int size) {
    auto* v = static_cast<std::vector<uint8_t>*>(out);
    v->insert(v->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
  }, &jpeg, 16, 16, 3, rgb.data(), 90);
  std::ofstream(broken + "/short.jpg", std::ios::binary).write(reinterpret_cast<const char*>(jpeg.data()), std::streamsize(jpeg.size() / 2));
  // A colmap that crashes as COLMAP 3.8 does on a database with no features.
  const std::string bin = temp("crashing_colmap");
  fs::create_directories(bin);
  std::ofstream(bin + "/colmap") << "#!/bin/sh\n"
                                    "echo 'F20261127 12:42:32.474221 17150 cache.h:132] Check failed: max_num_elems > 0 (0 vs. 0) '\n"
                                    "echo '*** Check failure stack trace: ***'\n"
                                    "echo '    @     0x7fa6ecd278ec  (unknown)'\n"
                                    "exit 134\n";
  fs::permissions(bin + "/colmap", fs::perms::owner_all);
  const std::string photos = photoFolder("photos_for_colmap", 3), processed = temp("processed");
  runCases({
      {"camera path that is a folder", "render " + model + " --path " + folder + " -o " + temp("r"), 1,
       "'" + folder + "' is a folder, not a camera path (a JSON file)", "basic_filebuf"},
      {"nerfstudio fov 1e-30", "render " + model + " --path " + narrow + " -o " + temp("r"), 1,
       narrow + ": camera_path[0]: focal length y (fov) value", "fl_"},
      {"JSON into /proc", "eval " + model + " " + scene() + " --json /proc/vknerf.json", 1,
       "(folder /proc does not take new files)", "does not exist"},
      {"photos vknerf cannot decode", "process " + broken + " -o " + temp("never_processed"), 1,
       "'" + broken + "': 2 of 5 photos cannot be decoded: notes.jpg (not a PNG or JPEG file); short.jpg (", "colmap"},
      {"COLMAP crashing", "process " + photos + " -o " + processed, 1,
       "COLMAP failed at feature extraction (colmap feature_extractor, exit status 134): Check failed: max_num_elems > 0 "
       "(0 vs. 0); log: " + processed + ".colmap.log", "(unknown)", "PATH=" + bin + ":$PATH"},
      {"negative mesh threshold", "export mesh " + model + " -o " + temp("m.ply") + " --threshold -1", 2,
       "--threshold must be a positive density, got -1"},
      {"--max-points 0 documented", "export points --help", 0, "(default 0: all)"},
      {"--max-images 0 documented", "process --help", 0, "(default 0: all)"},
  });
  EXPECT_FALSE(fs::exists(temp("m.ply")));
  EXPECT_FALSE(fs::exists(temp("never_processed")));
}

// A flag out of range or empty is a usage error naming it; `bench scenes` refuses a bad --vknerf
// before it makes -o, and a failed child's row gives the child's error, not its help footer; a
// pipe is not called a folder; a program that never started leaves no log.
TEST(BadInput, FlagsAndChildrenSayWhatIsWrong) {
  const std::string fast = tinyRefinedModel(), vknerf = std::string(VKNERF_BINARY_DIR) + "/vknerf";
  const std::string bench = "bench scenes " + scene() + " --steps 1 --config vanilla -o ";
  const std::string named = temp("bench_named"), twice = temp("bench_twice"), notVknerf = temp("bench_false");
  const fs::path pipeScene = temp("pipe_scene");
  fs::create_directories(pipeScene);
  ASSERT_EQ(::mkfifo((pipeScene / "poses_bounds.npy").c_str(), 0600), 0);
  const std::string noColmap = temp("no_colmap_bin"), photos = photoFolder("photos_without_colmap", 3);
  fs::create_directories(noColmap);
  const std::string processed = temp("processed_without_colmap");
  runCases({
      {"eval --appearance past the photos", "eval " + fast + " " + scene() + " --downscale 4 --appearance 100", 2,
       "eval: --appearance 100 is out of range: the model was trained on 100 photos (0..99)", "PSNR"},
      {"render --appearance past the photos", "render " + fast + " --orbit 1 --size 8 --appearance 100 -o " + temp("a_render"),
       2, "render: --appearance 100 is out of range"},
      {"an empty output", "export mesh " + tinyModel() + " -o ''", 2, "export mesh: -o,--output was given an empty value"},
      {"an empty scene", "train '' -o " + temp("empty.vknerf"), 2, "train: scene was given an empty value"},
      {"--vknerf NAME= without a binary", bench + named + " --vknerf a=", 2,
       "bench scenes: --vknerf a=: no binary after '='"},
      {"--vknerf =BINARY without a name", bench + named + " --vknerf =" + vknerf, 2,
       "bench scenes: --vknerf =" + vknerf + ": no name before '='"},
      {"two builds of one name", bench + twice + " --vknerf x=" + vknerf + " --vknerf x=/bin/true", 2,
       "bench scenes: --vknerf: two builds would both be named \"x\""},
      {"a build that is no vknerf", bench + notVknerf + " --vknerf f=/bin/false", 1, "/bin/false train --help: failed"},
      {"a --train-arg no build knows", bench + temp("bench_unknown_arg") + " --train-arg=--no-such-flag", 2,
       "bench scenes: --train-arg --no-such-flag: the train of build "},
      {"a child failing on a --train-arg", bench + temp("bench_bad_arg") + " --train-arg=--log-every=0", 1,
       "train failed (exit 2): --log-every: Value 0 not in range 1 to 1000000"},
      {"a pipe named poses_bounds.npy", "train " + (pipeScene / "poses_bounds.npy").string() + " -o " + temp("pipe.vknerf"), 1,
       "is neither a file nor a folder (a pipe or a device)"},
      {"process without COLMAP", "process " + photos + " -o " + processed, 1, "colmap is not installed", "", "PATH=" + noColmap},
  });
  for (const std::string& dir : {named, twice, notVknerf, temp("bench_unknown_arg")}) EXPECT_FALSE(fs::exists(dir)) << dir;
  ASSERT_TRUE(fs::exists(temp("bench_bad_arg") + "/scenes.md"));
  EXPECT_EQ(bytesOf(temp("bench_bad_arg") + "/scenes.md").find("Run with --help"), std::string::npos);
  EXPECT_FALSE(fs::exists(processed + ".colmap.log"));
  EXPECT_FALSE(fs::exists(processed));
}

// Whether a process whose command line holds `part` is running (read from /proc).
// The command line of the process /proc/PID names; "" once it has ended. A process that ends while
// it is read fails the read with ESRCH (which an ifstream throws on): tests run beside others.
static std::string commandLineOf(const fs::path& proc) {
  const int fd = ::open((proc / "cmdline").c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";
  std::string out;
  char buf[4096];
  ssize_t n;
  while ((n = ::read(fd, buf, sizeof buf)) > 0) out.append(buf, size_t(n));
  ::close(fd);
  return n < 0 ? "" : out;
}

static bool running(const std::string& part) {
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string pid = e.path().filename().string();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmdline = commandLineOf(e.path());
    for (char& c : cmdline)
      if (c == '\0') c = ' ';
    if (cmdline.find(part) != std::string::npos && cmdline.find("vknerf") != std::string::npos &&
        cmdline.find("/bin/sh") == std::string::npos)
      return true;
  }
  return false;
}

// `bench scenes` stopped passes the signal on to its child and waits for it: the train saves its
// model, no child is left running, and the exit status is the signal's; `process` does the same
// with COLMAP. A `train --summary` into a pipe nobody reads cannot outlive a signal.
TEST(BadInput, SignalsReachChildrenAndBlockedWrites) {
  const std::string tiny = " --train-arg=--width=16 --train-arg=--depth=2 --train-arg=--coarse=8 --train-arg=--fine=8 "
                           "--train-arg=--rays=128 --train-arg=--log-every=1";
  for (const auto& [signal, code] : {std::pair<std::string, int>{"TERM", 143}, {"INT", 130}}) {
    SCOPED_TRACE(signal);
    const std::string dir = temp("bench_stopped_" + signal), log = dir + "/runs/tabletop.train.log";
    auto r = runCli("bench scenes " + scene() + " --steps 100000 --config vanilla --downscale 4 -o " + dir + tiny +
                    " > " + dir + ".out 2>&1 & pid=$!; " + shellWaitUntil("grep -q '^step ' " + log + " 2>/dev/null") +
                    "kill -" + signal + " $pid; wait $pid; s=$?; cat " + dir + ".out; exit $s");
    EXPECT_EQ(r.code, code) << r.output;
    EXPECT_NE(r.output.find("bench scenes: stopped by SIG" + signal), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("train failed (exit " + std::to_string(code) + ")"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::exists(dir + "/runs/tabletop.vknerf")) << "the child did not save before the parent ended";
    EXPECT_FALSE(running(dir)) << "a child of the stopped bench is still running";
  }
  const std::string fifo = temp("summary_pipe"), model = temp("fifo.vknerf"), out = temp("fifo.out");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // A watchdog ends the train if the signal does not, so that a failure cannot hang the test; its
  // output goes elsewhere, or its sleep would hold the test's pipe open for 30 s after it is killed.
  auto r = runCli("train " + scene() + " -o " + model + kTiny + " --steps 1 --summary " + fifo + " > " + out +
                  " 2>&1 & pid=$!; " + shellWaitUntil("grep -q 'model saved to' " + out) + "sleep 0.5; kill -TERM $pid; (sleep 30; kill -KILL $pid) >/dev/null 2>&1 & dog=$!; "
                  "wait $pid; s=$?; kill $dog; cat " + out + "; exit $s");
  EXPECT_EQ(r.code, 143) << r.output;
  EXPECT_NE(r.output.find("model saved to " + model), std::string::npos) << r.output;
  struct stat st;
  ASSERT_EQ(::stat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));

  // `process` passes a signal on to COLMAP (here a stand-in that sleeps), waits for it and removes
  // what it staged.
  const std::string bin = temp("sleeping_colmap"), pidFile = temp("colmap.pid"), said = temp("process.out");
  fs::create_directories(bin);
  std::ofstream(bin + "/colmap") << "#!/bin/sh\necho $$ > " + pidFile + "\nexec sleep 600\n";
  fs::permissions(bin + "/colmap", fs::perms::owner_all);
  const std::string photos = photoFolder("photos_for_stopped_colmap", 3), processed = temp("stopped_process");
  r = runCli("process " + photos + " -o " + processed + " > " + said + " 2>&1 & pid=$!; " + shellWaitUntil("test -s " + pidFile) +
             "kill -TERM $pid; wait $pid; s=$?; cat " + said + "; exit $s",
             "PATH=" + bin + ":$PATH");
  EXPECT_EQ(r.code, 143) << r.output;
  EXPECT_NE(r.output.find("vknerf: stopped by SIGTERM"), std::string::npos) << r.output;
  std::string colmapPid = bytesOf(pidFile);
  while (!colmapPid.empty() && colmapPid.back() == '\n') colmapPid.pop_back();
  ASSERT_FALSE(colmapPid.empty());
  EXPECT_FALSE(fs::exists("/proc/" + colmapPid)) << "COLMAP outlived the stopped process";
  EXPECT_EQ(namesWith(fs::path(processed).parent_path().string(), "stopped_process"), std::vector<std::string>{});
}

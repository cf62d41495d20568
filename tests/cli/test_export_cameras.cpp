// `vknerf export cameras`: the transforms.json writer, the frames it is given (lib/camera_frames.h),
// and the command end to end: a scene made here, trained two steps, exported, read back by vknerf's
// own loader into the training cameras bit for bit; a checkpoint written before the cameras were
// recorded; an output over an input.
#include <gtest/gtest.h>

#include <bit>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/checkpoint/checkpoint.h"
#include "lib/camera_frames.h"
#include "lib/trained_poses.h"
#include "support/cli_run.h"
#include "support/dataset_files.h"
#include "support/error_message.h"
#include "support/gpu_test.h"
#include "support/sample_scene.h"
#include "support/tiny_config.h"
#include "vknerf/trainer.h"
#include "vknerf/transforms_file.h"

using namespace vknerf;
namespace fs = std::filesystem;
using nlohmann::json;
using test::runCli;

namespace {

std::vector<uint32_t> bitsOf(const Camera& c) {
  std::vector<uint32_t> b = {c.width, c.height, uint32_t(c.lens.model)};
  for (float v : {c.fx, c.fy, c.cx, c.cy, c.lens.k1, c.lens.k2, c.lens.k3, c.lens.k4, c.lens.k5, c.lens.k6, c.lens.p1,
                  c.lens.p2})
    b.push_back(std::bit_cast<uint32_t>(v));
  for (float v : c.c2w) b.push_back(std::bit_cast<uint32_t>(v));
  return b;
}

std::string canonical(const std::string& path) { return fs::weakly_canonical(path).string(); }

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Six 32x24 photos around the origin in images/, every lens the loader reads: an OpenCV lens, a
// fisheye, and pinholes with the principal point off centre; the poses in transforms_train.json.
fs::path lensScene(const fs::path& dir) {
  json frames = json::array();
  for (int i = 0; i < 6; ++i) {
    const std::string name = "images/p" + std::to_string(i) + ".png";
    test::writePng(dir / name, test::patternImage(32, 24, uint32_t(i)));
    const double a = 1.047 * i;
    json f = {{"file_path", name},
              {"transform_matrix", test::matrixJson(test::poseLookingAt({3 * std::cos(a), 3 * std::sin(a), 1}, {0, 0, 0}))},
              {"cx", 15.25 + i}, {"cy", 12.5}};
    if (i == 0) f.update({{"camera_model", "OPENCV"}, {"k1", 0.02}, {"k2", -0.01}, {"k3", 0.001}, {"p1", 0.001}, {"p2", -0.002}});
    if (i == 1) f.update({{"camera_model", "OPENCV_FISHEYE"}, {"k1", 0.01}, {"k2", -0.002}, {"k3", 0.0003}, {"k4", -0.0001}});
    frames.push_back(f);
  }
  test::writeJson(dir / "transforms_train.json", {{"fl_x", 30.1}, {"fl_y", 29.7}, {"frames", frames}});
  return dir;
}

// The smallest vanilla model (--coarse/--fine are vanilla's flags): the cameras it records are any model's.
const std::string kTiny = " --config vanilla --width 16 --depth 2 --coarse 8 --fine 8 --rays 128";

}  // namespace

TEST(TransformsFile, EachLensInTheKeysTheLoaderReads) {
  TrainedCamera pinhole{"a.png", pinholeFromFocal(8, 6, 7.5f, lookAt({0, -3, 0}, {0, 0, 0}, {0, 0, 1}))};
  TrainedCamera opencv = pinhole, fisheye = pinhole, unnamed = pinhole;
  opencv.camera.lens = {LensModel::OpenCV, 0.1f, 0.2f, 0.3f, 0, 0, 0, 0.4f, 0.5f};
  fisheye.camera.lens = {LensModel::Fisheye, 0.1f, 0.2f, 0.3f, 0.4f};
  unnamed.name = "";
  const json j = json::parse(transformsJson({pinhole, opencv, fisheye, unnamed}));
  ASSERT_EQ(j.at("frames").size(), 4u);
  const json& f = j["frames"];
  EXPECT_EQ(f[0].at("file_path"), "a.png");
  EXPECT_EQ(f[0].at("w"), 8);
  EXPECT_EQ(f[0].at("h"), 6);
  EXPECT_EQ(f[0].at("fl_x").get<float>(), 7.5f);
  EXPECT_EQ(f[0].at("transform_matrix").size(), 4u);
  EXPECT_EQ(f[0].at("transform_matrix")[1][3].get<float>(), -3.0f);
  EXPECT_EQ(f[0].at("camera_model"), "PINHOLE");
  EXPECT_FALSE(f[0].contains("k1"));
  EXPECT_EQ(f[1].at("camera_model"), "OPENCV");
  EXPECT_EQ(f[1].at("p2").get<float>(), 0.5f);
  EXPECT_FALSE(f[1].contains("k4"));
  EXPECT_EQ(f[2].at("camera_model"), "OPENCV_FISHEYE");
  EXPECT_EQ(f[2].at("k4").get<float>(), 0.4f);
  EXPECT_FALSE(f[2].contains("p1"));
  EXPECT_FALSE(f[3].contains("file_path"));
  // OpenCV's rational terms have no key: refused, naming the camera, rather than written as
  // nerfstudio's k4 (another term).
  TrainedCamera rational = opencv;
  rational.camera.lens.k5 = 0.01f;
  const std::string msg = test::errorOf([&] { transformsJson({pinhole, rational}); });
  EXPECT_MESSAGE_HAS(msg, "camera 1 ('a.png'): its OpenCV lens has k5 = 0.01");
}

// A camera trained at --downscale k is scaled back up to its image; a name relative to the current
// folder becomes relative to the output's folder; an image of another size is not this camera's.
TEST(CameraFrames, FramesStateTheirImagesSizeAndPathFromTheOutput) {
  const test::TempDir tmp("camera_frames");
  test::writePng(tmp.path() / "images" / "a.png", test::patternImage(40, 30, 1));
  const std::string relative = fs::relative(tmp.path() / "images" / "a.png", fs::current_path()).string();
  ASSERT_TRUE(fs::path(relative).is_relative());
  Camera half = pinholeFromFocal(20, 15, 17.25f);
  half.cx = 9.75f;
  half.cy = 7.125f;
  const std::string output = tmp.file("out/transforms.json");
  const auto frames = nerf::framesForFile({{relative, half}, {"not/a/file.png", half}}, output);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].name, "../images/a.png");
  EXPECT_EQ(frames[0].camera.width, 40u);
  EXPECT_EQ(frames[0].camera.height, 30u);
  EXPECT_EQ(frames[0].camera.fx, 34.5f);
  EXPECT_EQ(frames[0].camera.cx, 19.5f);
  EXPECT_EQ(frames[0].camera.cy, 14.25f);
  EXPECT_EQ(frames[1].name, "not/a/file.png");
  EXPECT_EQ(bitsOf(frames[1].camera), bitsOf(half));
  const std::string absolute = (tmp.path() / "images" / "a.png").string();
  EXPECT_EQ(nerf::framesForFile({{absolute, half}}, output)[0].name, absolute);
  const std::string msg = test::errorOf([&] { nerf::framesForFile({{absolute, pinholeFromFocal(30, 15, 10)}}, output); });
  EXPECT_MESSAGE_HAS(msg, "camera 0: image '" + absolute + "' is 40x30, neither the 30x15 it was trained at");
}

class TrainedCameras : public test::GpuTest {};

// The Trainer's model gives what save() records, and the checkpoint gives it back.
// vknerf eval with camera refinement: a view whose image a trained camera names takes that camera's
// pose, and only its pose (the evaluation's intrinsics may be another --downscale's).
TEST(TrainedPoses, ViewsOfTrainedPhotosTakeTheirPosesOnly) {
  Camera given;
  given.fx = given.fy = 50, given.cx = 20, given.cy = 15, given.width = 40, given.height = 30;
  std::vector<Camera> cameras(3, given);
  Camera refined = given;
  refined.fx = 100, refined.width = 80;  // trained at another size: not taken
  refined.c2w[3] = 0.25f, refined.c2w[7] = -0.5f;
  Camera other = given;
  other.c2w[11] = 9.0f;
  const auto used = nerf::useTrainedPoses(cameras, {"a.png", "b.png", "c.png"},
                                          {{"b.png", refined}, {"x.png", other}, {"", other}});
  EXPECT_EQ(used, 1u);
  EXPECT_EQ(cameras[1].c2w, refined.c2w);
  EXPECT_EQ(cameras[1].fx, given.fx);
  EXPECT_EQ(cameras[1].width, given.width);
  EXPECT_EQ(cameras[0].c2w, given.c2w);
  EXPECT_EQ(cameras[2].c2w, given.c2w);
}

TEST_F(TrainedCameras, TrainerRecordsTheDatasetsCamerasAndNames) {
  const Dataset& data = test::quarterSizeSampleScene();
  Trainer trainer(test::sharedContext(), data, test::tinyVanillaConfig());
  trainer.step();
  const auto live = trainer.model().trainingCameras();
  ASSERT_EQ(live.size(), data.cameras.size());
  const test::TempDir tmp("trained_cameras");
  trainer.save(tmp.file("m.vknerf"));
  const auto saved = Model::load(test::sharedContext(), tmp.file("m.vknerf")).trainingCameras();
  ASSERT_EQ(saved.size(), data.cameras.size());
  for (size_t i = 0; i < data.cameras.size(); ++i) {
    EXPECT_EQ(live[i].name, data.names[i]);
    EXPECT_EQ(saved[i].name, data.names[i]);
    EXPECT_EQ(bitsOf(live[i].camera), bitsOf(data.cameras[i]));
    EXPECT_EQ(bitsOf(saved[i].camera), bitsOf(data.cameras[i]));
  }
}

// Trained at --downscale 2 from a path relative to the folder the commands run in; exported into a
// folder of the scene; loaded back at --downscale 2 by vknerf's loader: the same cameras, bit for
// bit, and the same images.
TEST(ExportCamerasCli, TheLoaderReadsBackTheTrainingCameras) {
  const test::TempDir tmp("export_cameras");
  const fs::path scene = lensScene(tmp.path() / "scene");
  const std::string model = tmp.file("m.vknerf"), out = (scene / "exported" / "transforms.json").string();
  fs::create_directories(scene / "exported");
  const std::string relativeScene = fs::relative(scene, fs::current_path()).string();
  auto r = runCli("train " + relativeScene + " -o " + model + " --downscale 2 --steps 2" + kTiny);
  ASSERT_EQ(r.code, 0) << r.output;
  r = runCli("export cameras " + model + " -o " + out);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output, "6 training cameras written to " + out + "\n");

  const Dataset trained = Dataset::load(scene.string(), {.downscale = 2});
  ASSERT_EQ(trained.cameras.size(), 6u);
  EXPECT_EQ(trained.cameras[0].lens.model, LensModel::OpenCV);
  EXPECT_EQ(trained.cameras[1].lens.model, LensModel::Fisheye);
  const auto recorded = Model::trainingCamerasOf(model);
  const Dataset back = Dataset::load(out, {.split = "all", .downscale = 2});
  ASSERT_EQ(recorded.size(), 6u);
  ASSERT_EQ(back.cameras.size(), 6u);
  for (size_t i = 0; i < 6; ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(canonical(recorded[i].name), canonical(trained.names[i]));
    EXPECT_EQ(bitsOf(recorded[i].camera), bitsOf(trained.cameras[i]));
    EXPECT_EQ(canonical(back.names[i]), canonical(trained.names[i]));
    EXPECT_EQ(bitsOf(back.cameras[i]), bitsOf(trained.cameras[i]));
  }
  const json file = json::parse(std::ifstream(out));
  EXPECT_EQ(file["frames"][2]["file_path"], "../images/p2.png");
  EXPECT_EQ(file["frames"][2]["w"], 32);
}

// A checkpoint written before the cameras were recorded renders and resumes as before; only export
// cameras fails, in one line naming the file and the field, until a resumed run records them.
TEST(ExportCamerasCli, AnOlderCheckpointSaysWhatItLacks) {
  const test::TempDir tmp("export_cameras_old");
  const fs::path scene = lensScene(tmp.path() / "scene");
  const std::string model = tmp.file("m.vknerf"), old = tmp.file("old.vknerf"), out = tmp.file("t.json");
  ASSERT_EQ(runCli("train " + scene.string() + " -o " + model + " --steps 1" + kTiny).code, 0);
  auto ck = io::Checkpoint::load(model);
  json record = json::parse(ck.config);
  ASSERT_TRUE(record.contains("training_cameras"));
  record.erase("training_cameras");
  ck.config = record.dump(2);
  ck.save(old);

  auto r = runCli("export cameras " + old + " -o " + out);
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_EQ(r.output.rfind("vknerf: error: " + old + ": checkpoint has no training_cameras (", 0), 0u) << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << r.output;
  EXPECT_FALSE(fs::exists(out));

  r = runCli("render " + old + " --orbit 1 --size 8 -o " + tmp.file("renders"));
  EXPECT_EQ(r.code, 0) << r.output;
  r = runCli("train " + scene.string() + " -o " + old + " --resume --steps 1");
  EXPECT_EQ(r.code, 0) << r.output;
  r = runCli("export cameras " + old + " -o " + out);
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(json::parse(std::ifstream(out))["frames"].size(), 6u);
}

// The model and the images the frames name are inputs: -o over one is a usage error naming both,
// and nothing is written.
TEST(ExportCamerasCli, AnOutputNeverReplacesTheModelOrAnImage) {
  const test::TempDir tmp("export_cameras_clash");
  const fs::path scene = lensScene(tmp.path() / "scene");
  const std::string model = tmp.file("m.vknerf"), image = (scene / "images" / "p3.png").string();
  ASSERT_EQ(runCli("train " + scene.string() + " -o " + model + " --steps 1" + kTiny).code, 0);
  const std::string modelBytes = bytesOf(model), imageBytes = bytesOf(image);
  auto r = runCli("export cameras " + model + " -o " + model);
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("export cameras: -o " + model + " would replace the model " + model + " (the same file)"),
            std::string::npos) << r.output;
  r = runCli("export cameras " + model + " -o " + image);
  EXPECT_EQ(r.code, 2) << r.output;
  // The image is also one of the scene's own files, which is checked first (before the frames are read).
  EXPECT_NE(r.output.find("-o " + image + " is one of the files of the scene "), std::string::npos) << r.output;
  EXPECT_EQ(bytesOf(model), modelBytes);
  EXPECT_EQ(bytesOf(image), imageBytes);
  EXPECT_EQ(runCli("export cameras " + model).code, 2);  // no -o
}

// The checkpoint's record of the training cameras (io/checkpoint/checkpoint_record.h): written and
// read back bit for bit, absent from an older checkpoint without harm elsewhere, and a malformed
// camera named by its field.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/checkpoint/checkpoint.h"
#include "io/checkpoint/checkpoint_record.h"
#include "support/error_message.h"
#include "vknerf/error.h"

using namespace vknerf;
using nlohmann::json;

namespace {

// A finite float of any exponent, subnormals and -0 included: every bit of the mantissa matters.
float anyFiniteFloat(std::mt19937& rng) {
  for (;;) {
    const float f = std::bit_cast<float>(uint32_t(rng()));
    if (std::isfinite(f)) return f;
  }
}

std::vector<TrainedCamera> randomCameras(uint32_t seed) {
  std::mt19937 rng(seed);
  const char* names[] = {"scene/./train/r_0.png", "", "photos/ünïcødé \"quoted\".JPG", "/abs/path/b.png"};
  std::vector<TrainedCamera> out;
  for (int i = 0; i < 12; ++i) {
    TrainedCamera t;
    t.name = names[i % 4];
    Camera& c = t.camera;
    c.width = 1 + rng() % 4000;
    c.height = 1 + rng() % 4000;
    c.fx = std::fabs(anyFiniteFloat(rng)) + 1e-30f;
    c.fy = std::fabs(anyFiniteFloat(rng)) + 1e-30f;
    c.cx = anyFiniteFloat(rng);
    c.cy = anyFiniteFloat(rng);
    for (float& v : c.c2w) v = anyFiniteFloat(rng);
    c.c2w[3] = -0.0f;
    c.lens.model = LensModel(i % 3);
    for (float* k : {&c.lens.k1, &c.lens.k2, &c.lens.k3, &c.lens.k4, &c.lens.k5, &c.lens.k6, &c.lens.p1, &c.lens.p2})
      *k = anyFiniteFloat(rng);
    out.push_back(t);
  }
  return out;
}

std::vector<uint32_t> bitsOf(const Camera& c) {
  std::vector<uint32_t> b = {c.width, c.height, uint32_t(c.lens.model)};
  for (float v : {c.fx, c.fy, c.cx, c.cy, c.lens.k1, c.lens.k2, c.lens.k3, c.lens.k4, c.lens.k5, c.lens.k6, c.lens.p1,
                  c.lens.p2})
    b.push_back(std::bit_cast<uint32_t>(v));
  for (float v : c.c2w) b.push_back(std::bit_cast<uint32_t>(v));
  return b;
}

// A checkpoint whose record holds `cameras`, as Trainer::save writes it; `edit` changes its JSON.
io::Checkpoint checkpointWith(const std::vector<TrainedCamera>& cameras,
                                const std::function<void(json&)>& edit = {}) {
  io::Checkpoint ck;
  ck.path = "model.vknerf";
  ck.config = io::CheckpointRecord::write(TrainConfig{}, 7, Aabb{}, {uint32_t(cameras.size()), 8, 8}, cameras);
  if (edit) {
    json j = json::parse(ck.config);
    edit(j);
    ck.config = j.dump(2);
  }
  return ck;
}

std::string camerasError(const io::Checkpoint& ck) {
  return test::errorOf([&] { io::CheckpointRecord(ck).trainingCameras(); });
}

}  // namespace

TEST(CheckpointRecord, TrainingCamerasReadBackBitForBit) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const auto cameras = randomCameras(seed);
    const auto back = io::CheckpointRecord(checkpointWith(cameras)).trainingCameras();
    ASSERT_EQ(back.size(), cameras.size());
    for (size_t i = 0; i < cameras.size(); ++i) {
      SCOPED_TRACE(i);
      EXPECT_EQ(back[i].name, cameras[i].name);
      EXPECT_EQ(bitsOf(back[i].camera), bitsOf(cameras[i].camera));
    }
  }
  EXPECT_TRUE(io::CheckpointRecord(checkpointWith({})).trainingCameras().empty());
}

// A checkpoint written before the cameras were recorded: the rest of its record reads as before,
// and only the cameras fail, in one line naming the file and the field.
TEST(CheckpointRecord, OlderCheckpointWithoutCamerasLoadsButHasNone) {
  const auto ck = checkpointWith(randomCameras(4), [](json& j) { j.erase("training_cameras"); });
  const io::CheckpointRecord record(ck);
  EXPECT_EQ(record.step(), 7u);
  EXPECT_NO_THROW(record.config());
  EXPECT_NO_THROW(record.bounds());
  EXPECT_NO_THROW(record.checkScene({.box = Aabb{}, .cameras = 12u}));
  const std::string msg = camerasError(ck);
  EXPECT_EQ(msg.rfind("model.vknerf: checkpoint has no training_cameras (", 0), 0u) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
}

TEST(CheckpointRecord, AMalformedCameraIsNamedByItsField) {
  const auto cameras = randomCameras(5);
  const std::vector<std::pair<std::function<void(json&)>, std::string>> cases = {
      {[](json& j) { j["training_cameras"] = 3; }, "model.vknerf: checkpoint training_cameras must be an array"},
      {[](json& j) { j["training_cameras"][1] = "camera"; }, "checkpoint training_cameras[1] must be an object"},
      {[](json& j) { j["training_cameras"][2].erase("fy"); }, "checkpoint training_cameras[2].fy is missing"},
      {[](json& j) { j["training_cameras"][2]["fx"] = -1; }, "training_cameras[2].fx must be positive"},
      {[](json& j) { j["training_cameras"][0]["cx"] = 1e300; }, "training_cameras[0].cx is not a finite 32-bit float"},
      {[](json& j) { j["training_cameras"][0]["cy"] = nullptr; }, "training_cameras[0].cy must be a number"},
      {[](json& j) { j["training_cameras"][3]["width"] = 0; }, "training_cameras[3].width must be a whole number"},
      {[](json& j) { j["training_cameras"][3]["height"] = 2.5; }, "training_cameras[3].height must be a whole number"},
      {[](json& j) { j["training_cameras"][4]["c2w"].erase(15); }, "training_cameras[4].c2w must be an array of 16"},
      {[](json& j) { j["training_cameras"][4]["c2w"][9] = "x"; }, "training_cameras[4].c2w[9] must be a number"},
      {[](json& j) { j["training_cameras"][5]["lens"]["model"] = "kb4"; }, "training_cameras[5].lens.model must be"},
      {[](json& j) { j["training_cameras"][5]["lens"].erase("p2"); }, "training_cameras[5].lens.p2 is missing"},
      {[](json& j) { j["training_cameras"][6]["name"] = 1; }, "training_cameras[6].name must be a string"},
  };
  for (const auto& [edit, expected] : cases) {
    const std::string msg = camerasError(checkpointWith(cameras, edit));
    EXPECT_NE(msg.find(expected), std::string::npos) << "expected '" << expected << "' in: " << msg;
    EXPECT_EQ(msg.rfind("model.vknerf: ", 0), 0u) << msg;
  }
}

// The training configuration as checkpoints store it: what is written reads back, and a model saved
// before a key existed reads as what it was then.
#include <gtest/gtest.h>

#include <limits>

#include "io/checkpoint/config_json.h"
#include "vknerf/error.h"

namespace vknerf {
namespace {

TrainConfig fastConfig(uint32_t featureWidth) {
  TrainConfig c;
  FastModel& m = c.model.emplace<FastModel>();
  m.featureWidth = featureWidth;
  return c;
}

TEST(ConfigJson, FeatureWidthRoundTrips) {
  for (uint32_t v : {16u, 12u, 0u}) {
    const TrainConfig back = nerf::trainConfigFromJson(nerf::toJson(fastConfig(v)), "m.vknerf");
    EXPECT_EQ(back.fastModel().featureWidth, v);
  }
}

// Models saved before the feature width was a setting passed the whole trunk width on (0 = width),
// whatever today's default is, so their parameters still line up.
TEST(ConfigJson, AModelWithoutAFeatureWidthPassesTheWholeWidth) {
  auto j = nerf::toJson(fastConfig(16));
  j["model"].erase("feature_width");
  EXPECT_EQ(nerf::trainConfigFromJson(j, "old.vknerf").fastModel().featureWidth, 0u);
}

TEST(ConfigJson, AFeatureWidthThatCannotWorkNamesTheKey) {
  for (uint32_t v : {6u, 128u}) {  // not a multiple of 4; wider than the 64-wide trunk
    try {
      nerf::trainConfigFromJson(nerf::toJson(fastConfig(v)), "bad.vknerf");
      ADD_FAILURE() << "feature width " << v << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("model.feature_width"), std::string::npos) << e.what();
    }
  }
}

// The distortion loss's weight is a training setting: written, read back, and 0 for a model saved
// before it existed (it trained without); a negative or non-finite weight names the key.
TEST(ConfigJson, DistortionLossRoundTripsAndDefaultsToNoneForOldModels) {
  TrainConfig c = fastConfig(16);
  c.fastModel().distortionLoss = 0.01f;
  EXPECT_EQ(nerf::trainConfigFromJson(nerf::toJson(c), "m.vknerf").fastModel().distortionLoss, 0.01f);
  auto j = nerf::toJson(c);
  j.erase("distortion_loss");
  EXPECT_EQ(nerf::trainConfigFromJson(j, "old.vknerf").fastModel().distortionLoss, 0.0f);
  for (float bad : {-0.5f, std::numeric_limits<float>::infinity()}) {
    c.fastModel().distortionLoss = bad;
    try {
      nerf::trainConfigFromJson(nerf::toJson(c), "bad.vknerf");
      ADD_FAILURE() << "distortion loss " << bad << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("distortion_loss"), std::string::npos) << e.what();
    }
  }
}

// The far field is part of the model (its parameters are in the checkpoint): written, read back,
// constant for a model saved before it existed; an unknown name is an error naming the key and file.
TEST(ConfigJson, FarFieldRoundTripsAndDefaultsToConstantForOldModels) {
  TrainConfig c = fastConfig(16);
  for (FarField f : {FarField::Constant, FarField::Learned}) {
    c.fastModel().farField = f;
    EXPECT_EQ(nerf::trainConfigFromJson(nerf::toJson(c), "m.vknerf").fastModel().farField, f);
  }
  auto j = nerf::toJson(c);
  j["model"].erase("far_field");
  EXPECT_EQ(nerf::trainConfigFromJson(j, "old.vknerf").fastModel().farField, FarField::Constant);
  j["model"]["far_field"] = "painted";
  try {
    nerf::trainConfigFromJson(j, "bad.vknerf");
    ADD_FAILURE() << "far field \"painted\" was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.vknerf"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("model.far_field"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vknerf

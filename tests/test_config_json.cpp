// The training configuration as checkpoints store it: what is written reads back, and a model saved
// before a key existed reads as what it was then.
#include <gtest/gtest.h>

#include "io/config_json.h"
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

}  // namespace
}  // namespace vknerf

// The training configuration as checkpoints store it: what is written reads back, and a model saved
// before a key existed reads as what it was then.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <set>

#include "io/checkpoint/config_json.h"
#include "support/error_message.h"
#include "vknerf/config_fields.h"
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
    const TrainConfig back = io::trainConfigFromJson(io::toJson(fastConfig(v)), "m.vknerf");
    EXPECT_EQ(back.fastModel().featureWidth, v);
  }
}

// Models saved before the feature width was a setting passed the whole trunk width on (0 = width),
// whatever today's default is, so their parameters still line up.
TEST(ConfigJson, AModelWithoutAFeatureWidthPassesTheWholeWidth) {
  auto j = io::toJson(fastConfig(16));
  j["model"].erase("feature_width");
  EXPECT_EQ(io::trainConfigFromJson(j, "old.vknerf").fastModel().featureWidth, 0u);
}

TEST(ConfigJson, AFeatureWidthThatCannotWorkNamesTheKey) {
  for (uint32_t v : {6u, 128u}) {  // not a multiple of 4; wider than the 64-wide trunk
    try {
      io::trainConfigFromJson(io::toJson(fastConfig(v)), "bad.vknerf");
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
  EXPECT_EQ(io::trainConfigFromJson(io::toJson(c), "m.vknerf").fastModel().distortionLoss, 0.01f);
  auto j = io::toJson(c);
  j.erase("distortion_loss");
  EXPECT_EQ(io::trainConfigFromJson(j, "old.vknerf").fastModel().distortionLoss, 0.0f);
  for (float bad : {-0.5f, std::numeric_limits<float>::infinity()}) {
    c.fastModel().distortionLoss = bad;
    try {
      io::trainConfigFromJson(io::toJson(c), "bad.vknerf");
      ADD_FAILURE() << "distortion loss " << bad << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("distortion_loss"), std::string::npos) << e.what();
    }
  }
}

// Whether the far field counts in the distortion loss: written, read back, and off for a model saved
// before the choice existed (its loss left the far field out).
TEST(ConfigJson, DistortionFarFieldRoundTripsAndIsOffForOldModels) {
  TrainConfig c = fastConfig(16);
  c.fastModel().distortionLoss = 0.001f;
  c.fastModel().distortionFarField = true;
  auto j = io::toJson(c);
  EXPECT_EQ(j["distortion_far_field"], true);
  EXPECT_TRUE(io::trainConfigFromJson(j, "m.vknerf").fastModel().distortionFarField);
  j.erase("distortion_far_field");
  EXPECT_FALSE(io::trainConfigFromJson(j, "old.vknerf").fastModel().distortionFarField);
}

// The proposal estimator's settings: written, read back, and off for a model saved before it existed
// (every marched sample through the field, no proposal arrays in its checkpoint).
TEST(ConfigJson, ProposalRoundTripsAndIsOffForOldModels) {
  TrainConfig c = fastConfig(16);
  c.fastModel().sampler = Sampler::Proposal;
  c.fastModel().proposalSamples = 24;
  c.fastModel().proposalLevels = 3;
  c.fastModel().proposalLoss = 0.5f;
  c.fastModel().proposalAnnealSteps = 300;
  auto j = io::toJson(c);
  EXPECT_EQ(j["proposal_samples"], 24);
  EXPECT_EQ(j["sampler"], "proposal");
  const FastModel back = io::trainConfigFromJson(j, "m.vknerf").fastModel();
  EXPECT_TRUE(back.usesProposal());
  EXPECT_EQ(back.proposalSamples, 24u);
  EXPECT_EQ(back.proposalLevels, 3u);
  EXPECT_EQ(back.proposalLoss, 0.5f);
  EXPECT_EQ(back.proposalAnnealSteps, 300u);
  // A model saved before the sampler's key sampled with the proposal where it had its samples.
  j.erase("sampler");
  EXPECT_EQ(io::trainConfigFromJson(j, "older.vknerf").fastModel().sampler, Sampler::Proposal);
  for (const char* key : {"proposal_samples", "proposal_levels", "proposal_loss", "proposal_anneal_steps", "proposal_stride"})
    j.erase(key);
  const FastModel old = io::trainConfigFromJson(j, "old.vknerf").fastModel();
  EXPECT_EQ(old.sampler, Sampler::March);
  EXPECT_FALSE(old.usesProposal());
  EXPECT_EQ(old.proposalLevels, 5u);
  EXPECT_EQ(old.proposalStride, 1u);
  EXPECT_EQ(old.proposalAnnealSteps, 0u);
}

// The sampler is a name: another is refused naming the key, and the proposal without its samples
// is refused (a checkpoint edited by hand).
TEST(ConfigJson, SamplerIsCheckedOnLoad) {
  TrainConfig c = fastConfig(16);
  c.fastModel().sampler = Sampler::Proposal;
  auto j = io::toJson(c);
  j["sampler"] = "importance";
  EXPECT_MESSAGE_HAS(test::errorOf([&] { io::trainConfigFromJson(j, "m.vknerf"); }),
                     "m.vknerf: checkpoint config: sampler must be auto, march or proposal, got \"importance\"");
  j["sampler"] = "proposal";
  j["proposal_samples"] = 0;
  EXPECT_MESSAGE_HAS(test::errorOf([&] { io::trainConfigFromJson(j, "m.vknerf"); }),
                     "sampler proposal needs proposal_samples >= 1, got 0");
  // A value outside the enumeration, as only the API can set, is refused by validate().
  c.fastModel().sampler = Sampler(7);
  EXPECT_MESSAGE_HAS(test::errorOf([&] { c.validate(); }), "sampler must be in [0, 2], got 7");
}

// The far field is part of the model (its parameters are in the checkpoint): written, read back,
// constant for a model saved before it existed; an unknown name is an error naming the key and file.
TEST(ConfigJson, FarFieldRoundTripsAndDefaultsToConstantForOldModels) {
  TrainConfig c = fastConfig(16);
  for (FarField f : {FarField::Constant, FarField::Learned}) {
    c.fastModel().farField = f;
    EXPECT_EQ(io::trainConfigFromJson(io::toJson(c), "m.vknerf").fastModel().farField, f);
  }
  auto j = io::toJson(c);
  j["model"].erase("far_field");
  EXPECT_EQ(io::trainConfigFromJson(j, "old.vknerf").fastModel().farField, FarField::Constant);
  j["model"]["far_field"] = "painted";
  try {
    io::trainConfigFromJson(j, "bad.vknerf");
    ADD_FAILURE() << "far field \"painted\" was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.vknerf"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("model.far_field"), std::string::npos) << e.what();
  }
}

// A checkpoint's configuration keeps the keys of the first format where older builds and older
// checkpoints expect them: the model's own under "model", the fast model's training fields at the
// top level. (Keys added later may be anywhere.)
TEST(ConfigJson, TheFirstFormatsKeysStayWhereTheyWere) {
  const auto keys = [](const nlohmann::json& j) {
    std::set<std::string> k;
    for (const auto& [key, value] : j.items()) k.insert(key);
    return k;
  };
  const auto has = [](const std::set<std::string>& all, const std::set<std::string>& some) {
    return std::includes(all.begin(), all.end(), some.begin(), some.end());
  };
  const std::set<std::string> common = {"background", "beta1", "beta2", "decay_steps", "epsilon", "lr", "lr_final",
                                        "model", "random_background", "rays_per_batch", "seed"};
  const nlohmann::json vanilla = io::toJson(TrainConfig{}), fast = io::toJson(fastConfig(16));
  EXPECT_TRUE(has(keys(vanilla), common)) << vanilla.dump();
  EXPECT_TRUE(has(keys(vanilla["model"]), {"name", "width", "depth", "skip_layer", "pos_levels", "dir_levels", "density",
                                           "coarse_samples", "fine_samples", "separate_fine"}))
      << vanilla.dump();
  EXPECT_TRUE(has(keys(fast), common)) << fast.dump();
  EXPECT_TRUE(has(keys(fast), {"samples_per_batch", "grid_update_interval", "grid_warmup_steps", "hash_lr_scale",
                               "early_termination", "distortion_loss"}))
      << fast.dump();
  EXPECT_TRUE(has(keys(fast["model"]), {"name", "width", "depth", "feature_width", "density", "hash_levels",
                                        "hash_features", "hash_log2_size", "hash_base_resolution", "hash_growth",
                                        "sh_degree", "grid_resolution", "cascades", "cone_angle", "near_distance",
                                        "march_steps", "max_samples_per_ray", "far_field"}))
      << fast.dump();
  EXPECT_EQ(vanilla["model"]["name"], "vanilla");
  EXPECT_EQ(fast["model"]["name"], "fast");
  EXPECT_EQ(fast["model"]["far_field"], "auto");                                // by name
  EXPECT_EQ(fast["model"]["density"], uint32_t(DensityActivation::TruncExp));  // by number
}

// A fast model saved by the first format (its keys only) loads as it trained then.
TEST(ConfigJson, AFastModelOfTheFirstFormatLoads) {
  const TrainConfig defaults = fastConfig(16);
  auto j = io::toJson(defaults);
  for (const char* later : {"feature_width", "hash_levels", "hash_features", "hash_log2_size", "hash_base_resolution",
                            "hash_growth", "sh_degree", "grid_resolution", "cascades", "cone_angle", "near_distance",
                            "march_steps", "max_samples_per_ray", "far_field"})
    j["model"].erase(later);
  for (const char* later : {"samples_per_batch", "grid_update_interval", "grid_warmup_steps", "hash_lr_scale",
                            "early_termination", "distortion_loss"})
    j.erase(later);
  const FastModel m = io::trainConfigFromJson(j, "first.vknerf").fastModel();
  EXPECT_EQ(m.featureWidth, 0u);  // the whole width
  EXPECT_EQ(m.cascades, 1u);
  EXPECT_EQ(m.nearDistance, 0.0f);
  EXPECT_EQ(m.distortionLoss, 0.0f);
  EXPECT_EQ(m.farField, FarField::Constant);
  EXPECT_EQ(m.hashLevels, defaults.fastModel().hashLevels);
  EXPECT_EQ(m.coneAngle, defaults.fastModel().coneAngle);
  EXPECT_EQ(m.samplesPerBatch, defaults.fastModel().samplesPerBatch);
}

// Every key of the first format is needed: without one, or with one of the wrong type, the message
// names the file and the key.
TEST(ConfigJson, AMissingOrMistypedFirstFormatKeyNamesFileAndKey) {
  for (const TrainConfig& c : {TrainConfig{}, fastConfig(16)}) {
    const auto j = io::toJson(c);
    for (const char* key : {"lr", "seed", "background"}) {
      auto broken = j;
      broken.erase(key);
      const std::string message = test::errorOf([&] { io::trainConfigFromJson(broken, "old.vknerf"); });
      EXPECT_MESSAGE_HAS(message, "old.vknerf: checkpoint config: ");
      EXPECT_MESSAGE_HAS(message, std::string("key '") + key + "' not found");
    }
    auto broken = j;
    broken["model"].erase("width");
    EXPECT_MESSAGE_HAS(test::errorOf([&] { io::trainConfigFromJson(broken, "old.vknerf"); }), "key 'width' not found");
    broken = j;
    broken["model"]["depth"] = "deep";
    EXPECT_MESSAGE_HAS(test::errorOf([&] { io::trainConfigFromJson(broken, "old.vknerf"); }),
                       "old.vknerf: checkpoint config: [json.exception.type_error.302]");
  }
}

// What is written reads back, for values other than the defaults too.
TEST(ConfigJson, EveryFieldRoundTrips) {
  TrainConfig v;
  v.vanillaModel().skipLayer = 3, v.vanillaModel().separateFineNetwork = false, v.background = {0.25f, 0.5f, 0};
  v.seed = 7, v.learningRate = 3e-3f;
  TrainConfig f = fastConfig(12);
  FastModel& m = f.fastModel();
  m.coneAngle = 1.0f / 64, m.cascades = 3, m.nearDistance = 0.1f, m.hashGrowth = 1.38f, m.earlyTermination = false;
  m.contraction = true, m.occupancyThreshold = 0.03f, m.stepOpacity = 0.05f;
  m.farField = FarField::Learned, m.density = DensityActivation::Softplus, m.distortionLoss = 0.001f;
  for (const TrainConfig& c : {v, f}) {
    const auto j = io::toJson(c);
    EXPECT_EQ(io::toJson(io::trainConfigFromJson(j, "m.vknerf")), j);
  }
}

// The table: a key and a flag name one field each; a field only the fast model reads says so in its
// flag's help, as `vknerf train --help` always did.
TEST(ConfigFields, KeysAndFlagsAreOneFieldEachAndFastFlagsSaySo) {
  std::set<std::string> vanillaKeys, fastKeys, flags;
  for (const ConfigField& f : configFields()) {
    if (f.vanilla) EXPECT_TRUE(vanillaKeys.insert(f.path()).second) << f.path();
    if (f.fast) EXPECT_TRUE(fastKeys.insert(f.path()).second) << f.path();
    EXPECT_TRUE(f.vanilla || f.fast) << f.path();
    if (!f.flag.name) continue;
    EXPECT_TRUE(flags.insert(f.flag.name).second) << f.flag.name;
    if (!f.vanilla) EXPECT_EQ(std::string(f.flag.help).rfind("fast", 0), 0u) << f.flag.name;
  }
}

}  // namespace
}  // namespace vknerf

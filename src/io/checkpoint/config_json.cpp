#include "io/checkpoint/config_json.h"

#include "vknerf/error.h"

namespace vknerf::nerf {

using nlohmann::json;

// The keys are those of the first checkpoint format, so older checkpoints still load: the model's
// own fields under "model", the fast model's training fields at the top level.
json toJson(const TrainConfig& c) {
  json j = {{"rays_per_batch", c.raysPerBatch}, {"lr", c.learningRate}, {"lr_final", c.learningRateFinal},
            {"decay_steps", c.decaySteps}, {"beta1", c.beta1}, {"beta2", c.beta2}, {"epsilon", c.epsilon},
            {"random_background", c.randomBackground}, {"background", c.background}, {"seed", c.seed}};
  if (const FastModel* m = std::get_if<FastModel>(&c.model)) {
    j["model"] = {{"name", "fast"}, {"width", m->width}, {"depth", m->depth}, {"feature_width", m->featureWidth}, {"density", uint32_t(m->density)},
                  {"hash_levels", m->hashLevels}, {"hash_features", m->hashFeatures},
                  {"hash_log2_size", m->hashLog2Size}, {"hash_base_resolution", m->hashBaseResolution},
                  {"hash_growth", m->hashGrowth}, {"sh_degree", m->shDegree},
                  {"grid_resolution", m->gridResolution}, {"cascades", m->cascades}, {"cone_angle", m->coneAngle}, {"near_distance", m->nearDistance}, {"march_steps", m->marchSteps},
                  {"max_samples_per_ray", m->maxSamplesPerRay}, {"far_field", farFieldName(m->farField)}};
    j["samples_per_batch"] = m->samplesPerBatch;
    j["grid_update_interval"] = m->gridUpdateInterval;
    j["grid_warmup_steps"] = m->gridWarmupSteps;
    j["hash_lr_scale"] = m->hashLearningRateScale;
    j["early_termination"] = m->earlyTermination;
    j["distortion_loss"] = m->distortionLoss;
  } else {
    const VanillaModel& v = std::get<VanillaModel>(c.model);
    j["model"] = {{"name", "vanilla"}, {"width", v.width}, {"depth", v.depth}, {"skip_layer", v.skipLayer},
                  {"pos_levels", v.posLevels}, {"dir_levels", v.dirLevels}, {"density", uint32_t(v.density)},
                  {"coarse_samples", v.coarseSamples}, {"fine_samples", v.fineSamples},
                  {"separate_fine", v.separateFineNetwork}};
  }
  return j;
}

namespace {

FarField farFieldOf(const std::string& name) {
  for (FarField f : {FarField::Auto, FarField::Constant, FarField::Learned})
    if (name == farFieldName(f)) return f;
  throw Error("model.far_field must be auto, constant or learned, got \"" + name + "\"");
}

FastModel fastModelFromJson(const json& m, const json& j) {
  FastModel f;
  f.width = m.at("width");
  f.depth = m.at("depth");
  f.featureWidth = m.value("feature_width", 0u);  // checkpoints from before it pass the whole width
  f.density = DensityActivation(m.at("density").get<uint32_t>());
  f.hashLevels = m.value("hash_levels", f.hashLevels);
  f.hashFeatures = m.value("hash_features", f.hashFeatures);
  f.hashLog2Size = m.value("hash_log2_size", f.hashLog2Size);
  f.hashBaseResolution = m.value("hash_base_resolution", f.hashBaseResolution);
  f.hashGrowth = m.value("hash_growth", f.hashGrowth);
  f.shDegree = m.value("sh_degree", f.shDegree);
  f.gridResolution = m.value("grid_resolution", f.gridResolution);
  f.cascades = m.value("cascades", 1u);  // checkpoints from before cascades have one
  f.coneAngle = m.value("cone_angle", f.coneAngle);
  f.nearDistance = m.value("near_distance", 0.0f);  // checkpoints from before it: the vanilla model's near plane
  f.marchSteps = m.value("march_steps", f.marchSteps);
  f.maxSamplesPerRay = m.value("max_samples_per_ray", f.maxSamplesPerRay);
  f.samplesPerBatch = j.value("samples_per_batch", f.samplesPerBatch);
  f.gridUpdateInterval = j.value("grid_update_interval", f.gridUpdateInterval);
  f.gridWarmupSteps = j.value("grid_warmup_steps", f.gridWarmupSteps);
  f.hashLearningRateScale = j.value("hash_lr_scale", f.hashLearningRateScale);
  f.earlyTermination = j.value("early_termination", f.earlyTermination);
  f.distortionLoss = j.value("distortion_loss", 0.0f);  // checkpoints from before it trained without
  f.farField = farFieldOf(m.value("far_field", std::string("constant")));  // as did checkpoints from before it
  return f;
}

VanillaModel vanillaModelFromJson(const json& m) {
  VanillaModel v;
  v.width = m.at("width");
  v.depth = m.at("depth");
  v.skipLayer = m.at("skip_layer");
  v.posLevels = m.at("pos_levels");
  v.dirLevels = m.at("dir_levels");
  v.density = DensityActivation(m.at("density").get<uint32_t>());
  v.coarseSamples = m.at("coarse_samples");
  v.fineSamples = m.at("fine_samples");
  v.separateFineNetwork = m.at("separate_fine");
  return v;
}

}  // namespace

TrainConfig trainConfigFromJson(const json& j, const std::string& file) {
  try {
    TrainConfig c;
    const json& m = j.at("model");
    const std::string name = m.at("name");
    if (name == "fast")
      c.model = fastModelFromJson(m, j);
    else if (name == "vanilla")
      c.model = vanillaModelFromJson(m);
    else
      throw Error("unknown model \"" + name + "\"");
    c.raysPerBatch = j.at("rays_per_batch");
    c.learningRate = j.at("lr");
    c.learningRateFinal = j.at("lr_final");
    c.decaySteps = j.at("decay_steps");
    c.beta1 = j.at("beta1");
    c.beta2 = j.at("beta2");
    c.epsilon = j.at("epsilon");
    c.randomBackground = j.at("random_background");
    c.background = j.at("background");
    c.seed = j.at("seed");
    c.validate();
    return c;
  } catch (const json::exception& e) {
    throw Error(file + ": checkpoint config: " + e.what());
  } catch (const Error& e) {
    throw Error(file + ": checkpoint config: " + e.what());
  }
}

}  // namespace vknerf::nerf

#include "io/config_json.h"

#include "vknerf/error.h"

namespace vknerf::nerf {

using nlohmann::json;

json toJson(const TrainConfig& c) {
  const ModelConfig& m = c.model;
  return {{"model",
           {{"name", m.name}, {"width", m.width}, {"depth", m.depth}, {"skip_layer", m.skipLayer},
            {"pos_levels", m.posLevels}, {"dir_levels", m.dirLevels}, {"density", uint32_t(m.density)},
            {"coarse_samples", m.coarseSamples}, {"fine_samples", m.fineSamples},
            {"separate_fine", m.separateFineNetwork}, {"hash_levels", m.hashLevels},
            {"hash_features", m.hashFeatures}, {"hash_log2_size", m.hashLog2Size},
            {"hash_base_resolution", m.hashBaseResolution}, {"hash_growth", m.hashGrowth},
            {"sh_degree", m.shDegree}, {"grid_resolution", m.gridResolution}, {"march_steps", m.marchSteps},
            {"max_samples_per_ray", m.maxSamplesPerRay}}},
          {"rays_per_batch", c.raysPerBatch}, {"lr", c.learningRate}, {"lr_final", c.learningRateFinal},
          {"decay_steps", c.decaySteps}, {"beta1", c.beta1}, {"beta2", c.beta2}, {"epsilon", c.epsilon},
          {"random_background", c.randomBackground}, {"background", c.background}, {"seed", c.seed},
          {"samples_per_batch", c.samplesPerBatch}, {"grid_update_interval", c.gridUpdateInterval},
          {"grid_warmup_steps", c.gridWarmupSteps}, {"hash_lr_scale", c.hashLearningRateScale},
          {"early_termination", c.earlyTermination}};
}

TrainConfig trainConfigFromJson(const json& j, const std::string& file) {
  try {
    TrainConfig c;
    const json& m = j.at("model");
    ModelConfig& mc = c.model;
    mc.name = m.at("name");
    mc.width = m.at("width");
    mc.depth = m.at("depth");
    mc.skipLayer = m.at("skip_layer");
    mc.posLevels = m.at("pos_levels");
    mc.dirLevels = m.at("dir_levels");
    mc.density = DensityActivation(m.at("density").get<uint32_t>());
    mc.coarseSamples = m.at("coarse_samples");
    mc.fineSamples = m.at("fine_samples");
    mc.separateFineNetwork = m.at("separate_fine");
    mc.hashLevels = m.value("hash_levels", mc.hashLevels);
    mc.hashFeatures = m.value("hash_features", mc.hashFeatures);
    mc.hashLog2Size = m.value("hash_log2_size", mc.hashLog2Size);
    mc.hashBaseResolution = m.value("hash_base_resolution", mc.hashBaseResolution);
    mc.hashGrowth = m.value("hash_growth", mc.hashGrowth);
    mc.shDegree = m.value("sh_degree", mc.shDegree);
    mc.gridResolution = m.value("grid_resolution", mc.gridResolution);
    mc.marchSteps = m.value("march_steps", mc.marchSteps);
    mc.maxSamplesPerRay = m.value("max_samples_per_ray", mc.maxSamplesPerRay);
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
    c.samplesPerBatch = j.value("samples_per_batch", c.samplesPerBatch);
    c.gridUpdateInterval = j.value("grid_update_interval", c.gridUpdateInterval);
    c.gridWarmupSteps = j.value("grid_warmup_steps", c.gridWarmupSteps);
    c.hashLearningRateScale = j.value("hash_lr_scale", c.hashLearningRateScale);
    c.earlyTermination = j.value("early_termination", c.earlyTermination);
    if (mc.name != "vanilla" && mc.name != "fast") throw Error(file + ": checkpoint config: unknown model \"" + mc.name + "\"");
    return c;
  } catch (const json::exception& e) {
    throw Error(file + ": checkpoint config: " + e.what());
  }
}

}  // namespace vknerf::nerf

// TrainConfig and its model descriptions (vknerf/config.h): names, the model accessors, describe().
// The configurations sized for a device (TrainConfig::vanilla, fast, named) ask the device, so they
// are the API's: src/api/config_presets.cpp.
#include "vknerf/config.h"

#include <sstream>

#include "vknerf/error.h"

namespace vknerf {

const char* modelName(const ModelConfig& model) {
  return std::holds_alternative<FastModel>(model) ? "fast" : "vanilla";
}

const char* farFieldName(FarField f) {
  switch (f) {
    case FarField::Auto: return "auto";
    case FarField::Constant: return "constant";
    case FarField::Learned: return "learned";
  }
  return "invalid";
}

const char* samplerName(Sampler s) {
  switch (s) {
    case Sampler::Auto: return "auto";
    case Sampler::March: return "march";
    case Sampler::Proposal: return "proposal";
  }
  return "invalid";
}

namespace {
template <class M, class Variant>  // Variant: ModelConfig or const ModelConfig
auto& modelOf(Variant& model) {
  if (auto* m = std::get_if<M>(&model)) return *m;
  throw Error(std::string("the configuration holds a ") + modelName(model) + " model");
}
}  // namespace

VanillaModel& TrainConfig::vanillaModel() { return modelOf<VanillaModel>(model); }
const VanillaModel& TrainConfig::vanillaModel() const { return modelOf<VanillaModel>(model); }
FastModel& TrainConfig::fastModel() { return modelOf<FastModel>(model); }
const FastModel& TrainConfig::fastModel() const { return modelOf<FastModel>(model); }

std::string TrainConfig::describe() const {
  std::ostringstream os;
  if (const FastModel* m = std::get_if<FastModel>(&model)) {
    os << "fast: hash grid L=" << m->hashLevels << " F=" << m->hashFeatures << " T=";
    if (m->hashLog2Size) os << m->hashLog2Size; else os << "auto";  // auto: from the dataset
    os << " N=" << m->hashBaseResolution << " b=";
    if (m->hashGrowth != 0) os << m->hashGrowth; else os << "auto";
    os << ", MLP " << m->depth << "x" << m->width << " (feature " << (m->featureWidth ? m->featureWidth : m->width) << ")"
       << ", SH degree " << m->shDegree << ", occupancy ";
    if (m->gridResolution) os << m->gridResolution << "^3"; else os << "auto";  // auto: from the march steps
    os << " x " << (m->cascades ? std::to_string(m->cascades) : std::string("auto")) << " cascades (cone angle " << m->coneAngle
       << "), near " << (m->nearDistance > 0 ? std::to_string(m->nearDistance) : std::string("auto")) << ", "
       << (m->marchSteps ? std::to_string(m->marchSteps) : std::string("auto")) << " steps per diagonal, ";
    // Streamed, not "~" + to_string(...): GCC 12 warns of a memcpy overlap in that operator+ (-Wrestrict, a false positive).
    if (m->samplesPerBatch) os << "~" << m->samplesPerBatch; else os << "auto";
    os << " samples/step";
    if (m->distortionLoss > 0) os << ", distortion loss " << m->distortionLoss << (m->distortionFarField ? " (far field counted)" : "");
    if (m->usesProposal())
      os << ", " << m->proposalSamples << " samples a ray placed by a proposal of " << m->proposalLevels << " levels";
    else if (m->sampler == Sampler::Auto)
      os << ", sampler auto";
    os << ", far field " << farFieldName(m->farField);
  } else {
    const VanillaModel& v = std::get<VanillaModel>(model);
    os << "vanilla: MLP " << v.depth << "x" << v.width << " (skip at " << v.skipLayer << "), gamma L=" << v.posLevels
       << "/" << v.dirLevels << ", samples " << v.coarseSamples << "+" << v.fineSamples
       << (v.separateFineNetwork ? ", coarse+fine networks" : ", one network") << ", " << raysPerBatch << " rays/step";
  }
  // `vknerf train` decays over its run instead (Trainer::setRunProgress); the rate holds after either.
  os << ", Adam lr " << learningRate << " -> " << learningRateFinal << " over " << decaySteps << " steps or a run";
  return os.str();
}

}  // namespace vknerf

#include "models/fast/proposal_field.h"

#include <algorithm>

namespace vknerf::models {

namespace {
constexpr uint32_t kLog2TableSize = 17;  // nerfacto's proposal networks' tables
constexpr uint32_t kWidth = 16;          // and their one hidden layer
}  // namespace

TrainConfig proposalConfigOf(const TrainConfig& config) {
  TrainConfig c = config;
  FastModel& m = c.fastModel();
  m.hashLevels = m.proposalLevels;
  m.hashFeatures = 2;
  m.hashLog2Size = std::min(m.hashLog2Size, kLog2TableSize);
  m.width = kWidth;
  m.depth = 1;
  m.featureWidth = 0;  // the whole layer
  m.shDegree = 1;      // its colour is never read: the smallest direction encoding
  m.appearanceDims = 0;
  c.seed = config.seed + 1;  // not the field's initial values
  return c;
}

float proposalAnneal(const FastModel& model, uint32_t step) {
  if (model.proposalAnnealSteps == 0) return 1.0f;
  const double x = std::min(1.0, double(step) / double(model.proposalAnnealSteps));
  constexpr double kBias = 10.0;  // nerfacto's proposal_weights_anneal_slope
  return float(kBias * x / ((kBias - 1.0) * x + 1.0));
}

}  // namespace vknerf::models

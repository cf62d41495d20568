#include "models/common/trainable_parameters.h"

#include <utility>

namespace vknerf::models {

nerf::AdamConfig adamConfigOf(const TrainConfig& config, float rateScale) {
  nerf::AdamConfig ac;
  ac.initialLearningRate = config.learningRate * rateScale;
  ac.decayRate = config.learningRateFinal / config.learningRate;
  ac.decaySteps = float(config.decaySteps);
  ac.decayEndStep = config.decaySteps;
  ac.beta1 = config.beta1;
  ac.beta2 = config.beta2;
  ac.epsilon = config.epsilon;
  return ac;
}

std::vector<nerf::ParameterRange> usedPartsOf(const nerf::HashEncoding& hash) {
  std::vector<nerf::ParameterRange> parts;
  for (const core::TableRun& r : core::hashGridUsedRuns(hash.config())) parts.push_back({uint32_t(r.first), uint32_t(r.count)});
  return parts;
}

TrainableParameters::TrainableParameters(Context& ctx, std::string name, const std::vector<float>& initial,
                                         const std::optional<nerf::AdamConfig>& adam, std::vector<nerf::ParameterRange> stepped)
    : name_(std::move(name)),
      count_(initial.size()),
      params_(gpu::Buffer::of(ctx, initial, "the trainable parameters")),
      stepped_(std::move(stepped)) {
  if (!adam) return;
  const VkDeviceSize bytes = count_ * sizeof(float);
  grads_ = gpu::Buffer::zeros(ctx, bytes, "the parameter gradients");
  m_ = gpu::Buffer::zeros(ctx, bytes, "Adam's first moments");
  v_ = gpu::Buffer::zeros(ctx, bytes, "Adam's second moments");
  adam_.emplace(ctx, *adam);
}

void TrainableParameters::recordOptimizerStep(gpu::Recorder& rec, nerf::OptimizerStep at) {
  // Adam counts steps from 1 (bias correction); the rate schedule from 0.
  adam_->record(rec, {uint32_t(count_), params_, grads_, m_, v_, stepped_}, at.step + 1, adam_->config().learningRate(at.rateStep));
}

void TrainableParameters::appendState(std::vector<StateArray>& out) {
  out.push_back({name_ + ".params", &params_, count_, false});
  if (!adam_) return;
  out.push_back({name_ + ".adam_m", &m_, count_, true});
  out.push_back({name_ + ".adam_v", &v_, count_, true});
}

}  // namespace vknerf::models

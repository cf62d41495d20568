#pragma once
// One set of trainable parameters (a network's weights, a hash table) and, when training, its
// gradient and Adam's moments with the optimizer that steps them. Both models are built from these.
#include <optional>
#include <string>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/common/parameter_groups.h"
#include "nerf/optim/adam.h"
#include "vknerf/config.h"

namespace vknerf::models {

// Adam's rates and moments as a training configuration sets them: the learning rate decays
// exponentially from learningRate to learningRateFinal over decaySteps and holds there, times
// `rateScale`.
nerf::AdamConfig adamConfigOf(const TrainConfig& config, float rateScale = 1.0f);

class TrainableParameters final : public ParameterGroup {
 public:
  // Without `adam`: parameters only (inference). Gradients and moments start at zero. `stepped`:
  // the parts Adam steps (AdamState::stepped; empty: all), where the rest is never given a gradient.
  TrainableParameters(Context& ctx, std::string name, const std::vector<float>& initial,
                      const std::optional<nerf::AdamConfig>& adam, std::vector<nerf::ParameterRange> stepped = {});

  size_t count() const { return count_; }
  size_t parameterCount() const override { return count_; }
  gpu::Buffer& params() { return params_; }
  gpu::Buffer& grads() { return grads_; }

  // Adam's update for training step `at` at the configured rate schedule; zeroes grads.
  void recordOptimizerStep(gpu::Recorder& rec, nerf::OptimizerStep at) override;
  // "<name>.params" and, when training, "<name>.adam_m" and "<name>.adam_v", for checkpoints.
  void appendState(std::vector<StateArray>& out) override;

 private:
  std::string name_;
  size_t count_;
  gpu::Buffer params_, grads_, m_, v_;
  std::optional<nerf::Adam> adam_;
  std::vector<nerf::ParameterRange> stepped_;
};

}  // namespace vknerf::models

#pragma once
// One set of trainable parameters (a network's weights, a hash table) and, when training, its
// gradient and Adam's moments with the optimizer that steps them. Both models are built from these.
#include <optional>
#include <string>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/recorder.h"
#include "models/field_pipeline.h"
#include "nerf/optim/adam.h"

namespace vknerf::nerf {

// Adam's rates and moments as a training configuration sets them: the learning rate decays
// exponentially from learningRate to learningRateFinal over decaySteps and holds there, times
// `rateScale`.
AdamConfig adamConfigOf(const TrainConfig& config, float rateScale = 1.0f);

class TrainableParameters {
 public:
  // Without `adam`: parameters only (inference). Gradients and moments start at zero.
  TrainableParameters(Context& ctx, std::string name, const std::vector<float>& initial,
                      const std::optional<AdamConfig>& adam);

  size_t count() const { return count_; }
  gpu::Buffer& params() { return params_; }
  gpu::Buffer& grads() { return grads_; }

  // Adam's update for training step `at` at the configured rate schedule; zeroes grads.
  void recordOptimizerStep(gpu::Recorder& rec, OptimizerStep at);
  // "<name>.params" and, when training, "<name>.adam_m" and "<name>.adam_v", for checkpoints.
  void appendState(std::vector<StateArray>& out);

 private:
  std::string name_;
  size_t count_;
  gpu::Buffer params_, grads_, m_, v_;
  std::optional<Adam> adam_;
};

}  // namespace vknerf::nerf

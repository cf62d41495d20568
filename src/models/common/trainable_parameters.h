#pragma once
// One set of trainable parameters (a network's weights, a hash table) and, when training, its
// gradient and Adam's moments with the optimizer that steps them. Both models are built from these.
#include <optional>
#include <string>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/field_pipeline.h"
#include "nerf/encoding/hash_encoding.h"
#include "nerf/optim/adam.h"

namespace vknerf::models {

// Adam's rates and moments as a training configuration sets them: the learning rate decays
// exponentially from learningRate to learningRateFinal over decaySteps and holds there, times
// `rateScale`.
nerf::AdamConfig adamConfigOf(const TrainConfig& config, float rateScale = 1.0f);

// The parts of a hash table that a lookup can reach (core::hashGridUsedRuns), as
// TrainableParameters' `stepped`: Adam's dense step would otherwise run over the unused end of each
// dense level's slot too (2^17 entries a level on the 800x800 object: 27% of the table).
std::vector<nerf::ParameterRange> usedPartsOf(const nerf::HashEncoding& hash);

class TrainableParameters {
 public:
  // Without `adam`: parameters only (inference). Gradients and moments start at zero. `stepped`:
  // the parts Adam steps (AdamState::stepped; empty: all), where the rest is never given a gradient.
  TrainableParameters(Context& ctx, std::string name, const std::vector<float>& initial,
                      const std::optional<nerf::AdamConfig>& adam, std::vector<nerf::ParameterRange> stepped = {});

  size_t count() const { return count_; }
  gpu::Buffer& params() { return params_; }
  gpu::Buffer& grads() { return grads_; }

  // Adam's update for training step `at` at the configured rate schedule; zeroes grads.
  void recordOptimizerStep(gpu::Recorder& rec, nerf::OptimizerStep at);
  // "<name>.params" and, when training, "<name>.adam_m" and "<name>.adam_v", for checkpoints.
  void appendState(std::vector<StateArray>& out);

 private:
  std::string name_;
  size_t count_;
  gpu::Buffer params_, grads_, m_, v_;
  std::optional<nerf::Adam> adam_;
  std::vector<nerf::ParameterRange> stepped_;
};

}  // namespace vknerf::models

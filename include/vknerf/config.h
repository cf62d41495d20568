#pragma once
// Model and training configuration. `vanilla()` is the NeRF paper's recipe (positional encoding,
// coarse + fine MLPs, hierarchical sampling) scaled to the device: on a CPU device the network and
// sample counts are ones that converge in minutes on 100x100 images.
#include <array>
#include <cstdint>
#include <string>

#include "vknerf/context.h"

namespace vknerf {

enum class DensityActivation : uint32_t { Relu = 0, TruncExp = 1, Softplus = 2 };

struct ModelConfig {
  std::string name = "vanilla";
  uint32_t width = 256, depth = 8, skipLayer = 4;  // trunk: depth layers of width, gamma(x) re-injected at skipLayer
  uint32_t posLevels = 10, dirLevels = 4;          // frequency bands: 63 and 27 input dims
  DensityActivation density = DensityActivation::Relu;
  uint32_t coarseSamples = 64, fineSamples = 128;  // per ray
  bool separateFineNetwork = true;                 // paper: two networks; false: one network queried twice
};

struct TrainConfig {
  ModelConfig model;
  uint32_t raysPerBatch = 1024;
  float learningRate = 5e-4f, learningRateFinal = 5e-5f;  // exponential decay over `decaySteps`
  uint32_t decaySteps = 250000;
  float beta1 = 0.9f, beta2 = 0.999f, epsilon = 1e-7f;
  bool randomBackground = true;                           // empty space learns zero density
  std::array<float, 3> background{1, 1, 1};               // for evaluation and rendering
  uint32_t seed = 0;

  static TrainConfig vanilla(const Context& ctx);  // sized for the device
  std::string describe() const;                    // one line, printed at the start of training
};

}  // namespace vknerf

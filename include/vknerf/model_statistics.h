#pragma once
// What a model spends and how its samples fall (Trainer::statistics).
#include <cstdint>
#include <optional>
#include <vector>

namespace vknerf {

struct ModelStatistics {
  uint64_t mlpParameters = 0;       // every network's weights and biases
  uint64_t encodingParameters = 0;  // trainable encoding entries: the hash grid's (fast model), else 0
  double deviceMiB = 0;             // every device buffer the model's pipeline has allocated
  double samplesPerRay = 0;         // MLP queries per ray: coarse + fine (vanilla), marched in the last step (fast)
  uint32_t raysPerStep = 0;         // in the last step (the fast model adapts it)
  uint64_t samplesPerStep = 0;      // field evaluations in the last step
  // Fast model only.
  std::optional<double> occupiedFraction;     // occupancy-grid cells marked occupied
  std::vector<double> occupiedFractionPerCascade;  // the same per cascade, innermost first
  std::optional<double> occupiedBoxFraction;  // the occupied cells' bounding box over the scene box (volume)
  std::optional<double> meanSamplesPerRay;       // marched per ray, over all steps
  std::optional<double> keptByEarlyTermination;  // samples kept by early termination, over all steps
};

}  // namespace vknerf

#pragma once
// A model's state in one registry. Every trainable part (a network's weights, a hash table, the
// learned far field, the camera corrections, the appearance vectors) is a ParameterGroup: it steps
// its own optimizer, names its checkpoint arrays and counts its parameters. What is saved but not
// trained (the occupancy grid) is a StatePart. A model registers its parts once, in checkpoint
// order, and one loop steps, saves, loads and counts them all, so a new trainable part is one
// `add` call, not an edit of every place that lists them (nerfstudio's parameter groups).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/optim/adam.h"

namespace vknerf::models {

// A named float array of the model's state, for checkpoints.
struct StateArray {
  std::string name;
  gpu::Buffer* buffer;
  size_t count;
  bool optimizer;  // Adam moments: saved for resuming, not needed to render
  bool numbers = true;  // floats, checked finite on load; false for words of bits stored in float slots
};

class StatePart {
 public:
  virtual ~StatePart() = default;
  // Its arrays for the checkpoint, always in the same order.
  virtual void appendState(std::vector<StateArray>& out) = 0;
};

// What a group's parameters count as in ModelStatistics.
enum class ParameterRole { Network, Encoding, Other };

class ParameterGroup : public StatePart {
 public:
  // The optimizer's update for training step `at`; zeroes the gradients.
  virtual void recordOptimizerStep(gpu::Recorder& rec, nerf::OptimizerStep at) = 0;
  virtual size_t parameterCount() const = 0;
};

class ParameterGroups {
 public:
  // Registered parts must outlive the registry (they are the model's members). Checkpoint order is
  // registration order, state parts and groups alike.
  void add(ParameterGroup& group, ParameterRole role = ParameterRole::Other);
  void addState(StatePart& part);

  // Every group's optimizer step (a training step's last commands).
  void recordOptimizerSteps(gpu::Recorder& rec, nerf::OptimizerStep at);
  std::vector<StateArray> state();
  size_t parameterCount() const;
  size_t parameterCount(ParameterRole role) const;

 private:
  struct Entry {
    StatePart* part;
    ParameterGroup* group;  // null for a state part
    ParameterRole role;
  };
  std::vector<Entry> entries_;
};

}  // namespace vknerf::models

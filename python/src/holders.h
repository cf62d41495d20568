#pragma once
// What each Python object holds. Shared pointers keep alive what an object needs after its maker
// is gone: a trainer its context, a model its context (and a trainer's model that trainer), so
// Python may drop them in any order.
#include <memory>
#include <mutex>

#include "vknerf/context.h"
#include "vknerf/dataset.h"
#include "vknerf/trainer.h"

namespace vknerf::python {

struct PyContext {
  std::shared_ptr<Context> ctx;
};

struct PyDataset {
  std::shared_ptr<const Dataset> data;
};

// The GIL is released while a trainer steps and a model renders, so two Python threads may reach
// the same device objects at once: `busy` serialises them (a model's scratch buffers serve one
// render at a time, and a trainer's model changes as it steps).
struct TrainerState {
  std::shared_ptr<Context> ctx;
  std::unique_ptr<Trainer> trainer;
  std::mutex busy;
};

struct PyTrainer {
  std::shared_ptr<TrainerState> state;
};

struct PyModel {
  std::shared_ptr<Context> ctx;
  std::shared_ptr<const Model> model;  // a trainer's: aliases its TrainerState, which it keeps alive
  std::shared_ptr<std::mutex> busy;    // a trainer's: its mutex
};

}  // namespace vknerf::python

#include "vknerf/config.h"

#include <sstream>

namespace vknerf {

TrainConfig TrainConfig::vanilla(const Context& ctx) {
  TrainConfig c;
  if (ctx.isCpu()) {
    // The paper's 8x256 network with 64+128 samples needs days on a CPU. This keeps the recipe
    // (encodings, skip, late direction, coarse + fine) at a size that converges in minutes on
    // 100x100 images: ~1/60 of the paper's FLOPs per ray.
    c.model.width = 64;
    c.model.depth = 4;
    c.model.skipLayer = 2;
    c.model.coarseSamples = 32;
    c.model.fineSamples = 64;
    c.raysPerBatch = 1024;
    c.learningRate = 2e-3f;
    c.learningRateFinal = 2e-4f;
    c.decaySteps = 20000;
  } else {
    c.raysPerBatch = 4096;
  }
  return c;
}

std::string TrainConfig::describe() const {
  std::ostringstream os;
  os << model.name << ": MLP " << model.depth << "x" << model.width << " (skip at " << model.skipLayer << "), gamma L="
     << model.posLevels << "/" << model.dirLevels << ", samples " << model.coarseSamples << "+" << model.fineSamples
     << (model.separateFineNetwork ? ", coarse+fine networks" : ", one network") << ", " << raysPerBatch
     << " rays/step, Adam lr " << learningRate << " -> " << learningRateFinal << " over " << decaySteps << " steps";
  return os.str();
}

}  // namespace vknerf

#pragma once
// The vanilla recipe at tiny sizes, so that a training step costs milliseconds: for tests that train
// and compare, not for tests of quality.
#include "vknerf/config.h"

namespace vknerf::test {

inline TrainConfig tinyVanillaConfig() {
  TrainConfig c;
  VanillaModel& m = c.vanillaModel();
  m.width = 32;
  m.depth = 2;
  m.skipLayer = 1;
  m.posLevels = 4;
  m.dirLevels = 2;
  m.coarseSamples = 8;
  m.fineSamples = 8;
  c.raysPerBatch = 256;
  return c;
}

}  // namespace vknerf::test

#pragma once
// The shipped sample scene (assets/tabletop) at a quarter of its size, loaded once per test process:
// for tests that train a few steps on real views (with tiny_config.h's configuration).
#include <string>

#include "vknerf/dataset.h"

namespace vknerf::test {

inline const Dataset& quarterSizeSampleScene() {
  static Dataset d = [] {
    DatasetOptions o;
    o.downscale = 4;
    return Dataset::load(std::string(VKNERF_SOURCE_DIR) + "/assets/tabletop", o);
  }();
  return d;
}

}  // namespace vknerf::test

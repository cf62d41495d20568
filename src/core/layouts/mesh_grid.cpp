#include "core/layouts/mesh_grid.h"

namespace vknerf::core {

uint64_t GridLayout::cells() const {
  uint64_t c = 1;
  for (uint32_t k : n) c *= k > 1 ? k - 1 : 0;
  return c;
}

}  // namespace vknerf::core

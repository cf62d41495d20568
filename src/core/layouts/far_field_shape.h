#pragma once
// The shape of the learned far field (src/models/common/far_field.h): the colour a ray sees at
// infinity in its direction is an MLP of a hash grid read on the unit sphere; its CPU reference is
// tests/reference/render/far_field.h.
#include "core/layouts/hash_grid_layout.h"
#include "core/layouts/mlp_layout.h"

namespace vknerf::core {

struct FarFieldShape {
  HashGridConfig grid;
  DenseMlpShape mlp;  // inputs = grid.levels * grid.featuresPerLevel, outputs = 3
};

}  // namespace vknerf::core

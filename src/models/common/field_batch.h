#pragma once
// The field's inputs and outputs for up to `capacity` samples, as every model evaluates it:
// positions and directions (vec4 per sample), their encodings (the MLP's row strides), the field
// (vec4 rgb, sigma) and, when training, the field's gradient and the MLP's kept activations.
#include <cstdint>
#include <memory>

#include "gpu/memory/buffer.h"
#include "nerf/network/mlp.h"

namespace vknerf::models {

struct FieldBatch {
  FieldBatch() = default;
  // Zeroed, so a render recorded over the whole capacity never reads garbage.
  FieldBatch(Context& ctx, const nerf::NerfMlp& mlp, uint32_t capacity, bool training);

  // The first `count` rows as the MLP reads (the encodings) and writes them (the field).
  nerf::NerfRows mlpRows(uint32_t count) const { return {count, posFeatures, dirFeatures, field}; }

  uint32_t capacity = 0;
  gpu::Buffer positions, directions, posFeatures, dirFeatures, field;
  gpu::Buffer dField;                             // training
  std::unique_ptr<nerf::NerfMlp::Workspace> workspace;  // training: activations kept for backward
};

}  // namespace vknerf::models

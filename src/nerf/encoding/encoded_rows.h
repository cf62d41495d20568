#pragma once
// The rows an encoding runs over, as one value (as the MLPs take NerfRows / LayerRows).
#include <cstdint>
#include <optional>

#include "gpu/memory/buffer.h"

namespace vknerf::nerf {

// `count` vec4 inputs (positions or directions) and a row-major feature matrix of `count` rows of
// `stride` floats whose block starts at columnOffset (both multiples of 4): written by a forward
// pass, read as dL/dfeatures by a backward one. rowLimit (optional): a uint on the device (e.g. a
// sample total); only rows below it are encoded (forward) or add to the gradients (backward), the
// rest of the `count` rows are left untouched (shaders/gpu/row_limit.glsl). rowGather (optional,
// a forward in one chunk): row i of the batch is row rowGather[i] of inputs and features (a uint per
// row), as in NerfRows; the other rows are left.
struct EncodedRows {
  uint32_t count = 0;
  gpu::BufferRange inputs, features;
  uint32_t stride = 0, columnOffset = 0;
  std::optional<gpu::BufferRange> rowLimit;
  std::optional<gpu::BufferRange> rowGather;
};

}  // namespace vknerf::nerf

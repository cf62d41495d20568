#pragma once
// Where the field inputs of a batch of samples go (SamplePoints, PackedSamplePoints).
#include "gpu/memory/buffer.h"

namespace vknerf::nerf {

// Positions and directions, vec4 per sample.
struct PointBuffers {
  gpu::BufferRange positions, directions;
};

}  // namespace vknerf::nerf

#pragma once
// Where the field inputs of a batch of samples go (SamplePoints, PackedSamplePoints,
// ProposalSampler), and the box their positions are mapped from (shaders/sampling/box_position.glsl).
#include <string>

#include "gpu/memory/buffer.h"
#include "vknerf/camera.h"
#include "vknerf/error.h"

namespace vknerf::nerf {

// Positions and directions, vec4 per sample.
struct PointBuffers {
  gpu::BufferRange positions, directions;
};

// Throws vknerf::Error, naming `who`, where `box` is empty (or NaN) along an axis: the mapping
// onto [-1, 1]^3 divides by its sides.
inline void requireBoxNotEmpty(const char* who, const Aabb& box) {
  for (int k = 0; k < 3; ++k)
    if (!(box.max[k] > box.min[k]))
      throw Error(std::string(who) + ": scene box is empty along axis " + std::to_string(k));
}

}  // namespace vknerf::nerf

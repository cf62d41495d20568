#pragma once
// The density grid of a mesh export sampled block by block: kBlockSide^3 samples per block, only
// the blocks a caller lists (DensityGridSampler). Listing every block samples the whole grid; listing
// those near the occupancy grid's occupied cells skips the space a render never marches through.
#include <array>
#include <cstdint>
#include <vector>

#include "nerf/occupancy/occupancy_grid.h"
#include "core/layouts/mesh_grid.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

constexpr uint32_t kBlockSide = 4;
constexpr uint32_t kBlockSamples = kBlockSide * kBlockSide * kBlockSide;

struct SampleBlocks {
  std::array<uint32_t, 3> count{0, 0, 0};  // blocks per axis: ceil(samples / kBlockSide)
  std::vector<uint32_t> ids;               // listed blocks, x + count.x (y + count.y z), ascending
};

SampleBlocks allSampleBlocks(const core::GridLayout& layout);

// The blocks holding a corner of any grid cell that overlaps an occupied cell of `occupancy` (whose
// outermost cascade covers `sceneBox`): every such grid cell's corners are sampled, so the surface
// there is the whole grid's; elsewhere the grid keeps 0.
SampleBlocks occupiedSampleBlocks(const core::GridLayout& layout, const Aabb& sceneBox, const OccupancyBits& occupancy);

}  // namespace vknerf::nerf

#pragma once
// The field sampled on a grid, on the device (shaders/mesh/grid_*.comp), block by block
// (sample_blocks.h): the positions of one batch of slots of the listed blocks for the field, and
// the field's densities back into the grid. Samples of unlisted blocks are left as they are.
#include <array>
#include <cstdint>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/mesh/sample_blocks.h"
#include "core/layouts/mesh_grid.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

class DensityGridSampler {
 public:
  // blockIds: the listed blocks' ids (uint each, SampleBlocks::ids) on the device.
  DensityGridSampler(Context& ctx, const core::GridLayout& layout, const SampleBlocks& blocks,
                     const gpu::BufferRange& blockIds);
  // Slots in all: kBlockSamples per listed block.
  uint64_t slots() const { return slots_; }
  // count: at most 65,535 workgroups of 256.
  // positions (vec4) of slots [first, first + count), the scene box mapped onto [-1, 1]^3.
  void recordPositions(gpu::Recorder& rec, const Aabb& sceneBox, uint32_t first, uint32_t count,
                       const gpu::BufferRange& positions);
  // The grid's sample of slot first + i gets field[i].w, for i < count.
  void recordDensities(gpu::Recorder& rec, const gpu::BufferRange& field, uint32_t first, uint32_t count,
                       const gpu::BufferRange& grid);

 private:
  core::GridLayout layout_;
  std::array<uint32_t, 3> blockCount_;
  gpu::BufferRange blockIds_;
  uint64_t slots_;
  gpu::Kernel points_, densities_;
};

}  // namespace vknerf::nerf

#pragma once
// The field sampled on a grid, on the device (shaders/mesh/grid_*.comp): the grid's positions
// for one batch of the field, and the field's densities back into the grid.
#include <cstdint>

#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu/recorder.h"
#include "reference/mesh/marching_cubes.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

class DensityGridSampler {
 public:
  explicit DensityGridSampler(Context& ctx);
  // count: at most 65,535 workgroups of 256.
  // positions (vec4) of samples [first, first + count) of `layout`, the scene box mapped onto [-1, 1]^3.
  void recordPositions(gpu::Recorder& rec, const ref::GridLayout& layout, const Aabb& sceneBox, uint32_t first,
                       uint32_t count, const gpu::BufferRange& positions);
  // grid[first + i] = field[i].w for i < count.
  void recordDensities(gpu::Recorder& rec, const gpu::BufferRange& field, uint32_t first, uint32_t count,
                       const gpu::BufferRange& grid);

 private:
  gpu::Kernel points_, densities_;
};

}  // namespace vknerf::nerf

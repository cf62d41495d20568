#include "nerf/mesh/density_grid.h"
#include "mesh/grid_points_shared.h"
#include "mesh/grid_density_shared.h"

namespace vknerf::nerf {
namespace {

using PointsPush = glsl::GridPointsPush;
using DensityPush = glsl::GridDensityPush;
constexpr uint32_t kLocal = 256;

}  // namespace

DensityGridSampler::DensityGridSampler(Context& ctx, const core::GridLayout& layout, const SampleBlocks& blocks,
                                       const gpu::BufferRange& blockIds)
    : layout_(layout),
      blockCount_(blocks.count),
      blockIds_(blockIds),
      slots_(uint64_t(blocks.ids.size()) * kBlockSamples),
      points_(ctx, {gpu::shaders::grid_points, {gpu::Binding::Storage, gpu::Binding::Storage}, sizeof(PointsPush), {}}),
      densities_(ctx, {gpu::shaders::grid_density, {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                       sizeof(DensityPush), {}}) {}

void DensityGridSampler::recordPositions(gpu::Recorder& rec, const Aabb& b, uint32_t first, uint32_t count,
                                         const gpu::BufferRange& positions) {
  const core::GridLayout& g = layout_;
  PointsPush p{{g.n[0], g.n[1], g.n[2], 0},
               {blockCount_[0], blockCount_[1], blockCount_[2], 0},
               {g.origin[0], g.origin[1], g.origin[2], 0},
               {g.spacing[0], g.spacing[1], g.spacing[2], 0},
               {b.min[0], b.min[1], b.min[2], 0},
               {b.max[0], b.max[1], b.max[2], 0},
               first,
               count};
  rec.dispatch(points_, {positions, blockIds_}, p, gpu::groupsFor(count, kLocal), 1, 1, "grid_points");
}

void DensityGridSampler::recordDensities(gpu::Recorder& rec, const gpu::BufferRange& field, uint32_t first,
                                         uint32_t count, const gpu::BufferRange& grid) {
  const core::GridLayout& g = layout_;
  DensityPush p{{g.n[0], g.n[1], g.n[2], 0}, {blockCount_[0], blockCount_[1], blockCount_[2], 0}, first, count};
  rec.dispatch(densities_, {field, grid, blockIds_}, p, gpu::groupsFor(count, kLocal), 1, 1, "grid_density");
}

}  // namespace vknerf::nerf

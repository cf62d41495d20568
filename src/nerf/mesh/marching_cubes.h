#pragma once
// Marching cubes on the device (shaders/mesh/mc_*.comp; CPU twin tests/reference/mesh/): a density
// grid in a device buffer becomes a welded, indexed triangle mesh, read back to the host.
//   pass 1: a flag per grid edge that crosses the threshold, a triangle count per cell (the case
//           table as a storage buffer), each scanned (gpu::PrefixSum) in chunks;
//   pass 2: a vertex per crossed edge at its scanned rank, a cell's triangles at its scanned offset,
//           naming the vertices by their edges' ranks, so neighbouring cells share them.
// The scans run in chunks within one dispatch's reach; the chunks' totals come back to the host
// (one submission per chunk) and return as per-chunk bases. Output sizes are known only after
// pass 1, so extraction submits and waits.
#include <cstdint>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/prefix_sum.h"
#include "core/layouts/mesh_grid.h"
#include "vknerf/context.h"

namespace vknerf::nerf {

class MarchingCubes {
 public:
  // Samples per chunk (a multiple of 1024) on a device with `limits`, at most `limit` (0: no limit
  // of the caller's): 2^24 at most (64 MiB of flags), the device's group count and storage range
  // permitting.
  static constexpr uint64_t kMaxChunk = 1u << 24;
  static uint32_t chunkFor(const VkPhysicalDeviceLimits& limits, uint32_t limit);
  // chunkLimit: elements per scanned chunk, at most what one dispatch covers (tests lower it to
  // cover several chunks cheaply); 0: the most.
  explicit MarchingCubes(Context& ctx, uint32_t chunkLimit = 0);

  // The surface where `density` (one float per sample of `layout`) crosses `threshold`, inside on
  // the side of higher density, triangles counter-clockwise seen from outside.
  core::TriangleMesh extract(const gpu::Buffer& density, const core::GridLayout& layout, float threshold);

  // Samples per grid a device can take: the grid and its edge ranks within one binding, the edge
  // ids within 32 bits.
  static uint64_t maxPoints(Context& ctx);

 private:
  Context& ctx_;
  uint32_t chunk_;
  gpu::PrefixSum scan_;
  gpu::Buffer table_, flags_;
  gpu::Kernel countEdges_, countCells_, writeVertices_, writeTriangles_;
};

}  // namespace vknerf::nerf

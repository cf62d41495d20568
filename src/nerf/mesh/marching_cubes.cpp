#include "nerf/mesh/marching_cubes.h"

#include <algorithm>
#include <string>
#include <vector>

#include "core/layouts/marching_cubes_table.h"
#include "gpu/dispatch/recorder.h"
#include "vknerf/error.h"
#include "mesh/marching_cubes_shared.h"

namespace vknerf::nerf {
namespace {

using Push = glsl::MarchingCubesPush;

constexpr uint32_t kLocal = 256;  // shaders/mesh/marching_cubes.glsl
constexpr uint32_t kAlign = 1024;  // chunks start at multiples of this (binding offset alignment)

std::vector<gpu::Binding> storage(int count) { return std::vector<gpu::Binding>(count, gpu::Binding::Storage); }

}  // namespace

uint32_t MarchingCubes::chunkFor(const VkPhysicalDeviceLimits& limits, uint32_t limit) {
  // One dispatch of kLocal-wide groups, and PrefixSum's single scan_add dispatch for chunk + 1,
  // within the device's group count; a flags buffer within its storage range; and at most
  // kMaxChunk, since a device whose group count is 2^31 - 1 (NVIDIA) would otherwise get a chunk
  // past 32 bits (a 16 GiB flags buffer) where 2^24 samples already keep the dispatches full.
  const uint64_t reach = std::min<uint64_t>(uint64_t(limits.maxComputeWorkGroupCount[0]) * kLocal - 1,
                                            std::min<uint64_t>(kMaxChunk, limits.maxStorageBufferRange / 4));
  const uint64_t chunk = std::min<uint64_t>(limit ? limit : reach, reach) / kAlign * kAlign;
  if (chunk == 0) throw Error("marching cubes: chunks must hold at least " + std::to_string(kAlign) + " elements");
  return uint32_t(chunk);
}

uint64_t MarchingCubes::maxPoints(Context& ctx) {
  const uint64_t range = ctx.properties().limits.maxStorageBufferRange;
  // The edge ranks (3 uints per sample, plus one) are the largest binding; edge ids are 32-bit.
  return std::min<uint64_t>((range / 4 - 1) / 3, (uint64_t(UINT32_MAX) - 3) / 3);
}

MarchingCubes::MarchingCubes(Context& ctx, uint32_t chunkLimit)
    : ctx_(ctx),
      chunk_(chunkFor(ctx.properties().limits, chunkLimit)),
      scan_(ctx, chunk_ + 1),
      table_(gpu::Buffer::of(ctx, core::marchingCubesTable())),
      flags_(ctx, VkDeviceSize(chunk_) * 4, "the marching-cubes flags"),
      countEdges_(ctx, {gpu::shaders::mc_count_edges, storage(2), sizeof(Push), {}}),
      countCells_(ctx, {gpu::shaders::mc_count_cells, storage(3), sizeof(Push), {}}),
      writeVertices_(ctx, {gpu::shaders::mc_write_vertices, storage(4), sizeof(Push), {}}),
      writeTriangles_(ctx, {gpu::shaders::mc_write_triangles, storage(7), sizeof(Push), {}}) {}

core::TriangleMesh MarchingCubes::extract(const gpu::Buffer& density, const core::GridLayout& g, float threshold) {
  core::TriangleMesh mesh;
  const uint64_t points = g.points(), cells = g.cells();
  if (cells == 0) return mesh;
  if (points > maxPoints(ctx_))
    throw Error("marching cubes: a grid of " + std::to_string(points) + " samples exceeds the device's " +
                std::to_string(maxPoints(ctx_)) + "; lower the resolution");
  if (density.size() < points * 4) throw Error("marching cubes: the density buffer is smaller than the grid");
  const uint32_t edges = uint32_t(points * 3);
  Push push{{g.n[0], g.n[1], g.n[2], 0},
            {g.origin[0], g.origin[1], g.origin[2], 0},
            {g.spacing[0], g.spacing[1], g.spacing[2], 0},
            0, 0, chunk_, threshold};

  // Pass 1: scans of `total` elements chunk by chunk into `ranks`; returns the chunks' bases and
  // the grand total.
  gpu::Recorder rec(ctx_);
  auto scanChunks = [&](gpu::Kernel& count, std::initializer_list<gpu::BufferRange> inputs, uint32_t total,
                        gpu::Buffer& ranks, const char* label) {
    std::vector<uint32_t> bases;
    uint64_t sum = 0;
    for (uint32_t first = 0; first < total; first += chunk_) {
      const uint32_t n = std::min(chunk_, total - first);
      push.first = first, push.count = n;
      std::vector<gpu::BufferRange> b(inputs);
      b.push_back(flags_);
      rec.begin();
      rec.dispatch(count, std::span<const gpu::BufferRange>(b), &push, sizeof push, gpu::groupsFor(n, kLocal), 1, 1, label);
      scan_.record(rec, flags_, n, gpu::BufferRange(ranks, VkDeviceSize(first) * 4, VkDeviceSize(n + 1) * 4), n + 1);
      rec.end();
      rec.submitAndWait();
      bases.push_back(uint32_t(sum));
      sum += ranks.download<uint32_t>(1, VkDeviceSize(first + n) * 4)[0];  // before the next chunk overwrites it
      if (sum > UINT32_MAX / 3) throw Error("marching cubes: the mesh exceeds 32-bit indices; lower the resolution");
    }
    return std::pair(gpu::Buffer::of(ctx_, bases), uint32_t(sum));
  };
  gpu::Buffer edgeRanks(ctx_, (VkDeviceSize(edges) + 1) * 4, "the marching-cubes edge ranks");
  gpu::Buffer cellRanks(ctx_, (VkDeviceSize(cells) + 1) * 4, "the marching-cubes cell offsets");
  auto [edgeBases, vertices] = scanChunks(countEdges_, {density}, edges, edgeRanks, "mc_count_edges");
  auto [cellBases, triangles] = scanChunks(countCells_, {density, table_}, uint32_t(cells), cellRanks, "mc_count_cells");
  if (triangles == 0) return mesh;

  // Pass 2.
  gpu::Buffer positions(ctx_, VkDeviceSize(vertices) * 12, "the mesh vertices");
  gpu::Buffer indices(ctx_, VkDeviceSize(triangles) * 12, "the mesh triangles");
  rec.begin();
  for (uint32_t first = 0; first < edges; first += chunk_) {
    push.first = first, push.count = std::min(chunk_, edges - first);
    rec.dispatch(writeVertices_, {density, edgeRanks, edgeBases, positions}, push, gpu::groupsFor(push.count, kLocal),
                 1, 1, "mc_write_vertices");
  }
  for (uint32_t first = 0; first < cells; first += chunk_) {
    push.first = first, push.count = std::min<uint32_t>(chunk_, uint32_t(cells) - first);
    rec.dispatch(writeTriangles_, {density, table_, edgeRanks, edgeBases, cellRanks, cellBases, indices}, push,
                 gpu::groupsFor(push.count, kLocal), 1, 1, "mc_write_triangles");
  }
  rec.end();
  rec.submitAndWait();
  mesh.positions = positions.download<float>(size_t(vertices) * 3);
  mesh.triangles = indices.download<uint32_t>(size_t(triangles) * 3);
  return mesh;
}

}  // namespace vknerf::nerf

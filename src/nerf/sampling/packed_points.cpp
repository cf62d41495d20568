#include "nerf/sampling/packed_points.h"

#include <string>

#include "nerf/sampling/packed_layout.h"
#include "nerf/sampling/sample_layout.h"
#include "vknerf/error.h"
#include "sampling/march_points_shared.h"

namespace vknerf::nerf {
namespace {

using PointsPush = glsl::MarchPointsPush;

constexpr uint32_t kPointsLocal = 64;  // march_points.comp

using gpu::requireBytes;

}  // namespace

PackedSamplePoints::PackedSamplePoints(Context& ctx, uint32_t chunkRows)
    : kernel_(ctx, {gpu::shaders::march_points,
                    {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                     gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(PointsPush), {}}),
      limited_(ctx),
      chunkRows_(chunkRows) {
  if (chunkRows == 0 || chunkRows % kPointsLocal || chunkRows > kChunkRows)
    throw Error("PackedSamplePoints: chunk rows must be a positive multiple of 64 up to " + std::to_string(kChunkRows));
}

void PackedSamplePoints::record(gpu::Recorder& rec, uint32_t capacity, const gpu::BufferRange& rays,
                                const PackedSamples& batch, const Aabb& box, const PointBuffers& out, bool midpoints) {
  const gpu::BufferRange &samples = batch.samples, &sampleRay = batch.sampleRay, &totals = batch.totals;
  const gpu::BufferRange &positions = out.positions, &directions = out.directions;
  requireBoxNotEmpty("PackedSamplePoints", box);
  requireBytes("PackedSamplePoints", "samples", samples, uint64_t(capacity) * kSampleBytes);
  requireBytes("PackedSamplePoints", "sampleRay", sampleRay, uint64_t(capacity) * 4);
  requireBytes("PackedSamplePoints", "totals", totals, PackedLayout::kTotalsBytes);
  requireBytes("PackedSamplePoints", "positions", positions, uint64_t(capacity) * 16);
  requireBytes("PackedSamplePoints", "directions", directions, uint64_t(capacity) * 16);
  if (capacity == 0) return;
  // Over the capacity the dispatch was a few us of lavapipe time per idle workgroup: a render tile
  // of 2048 rays (capacity 131072 samples) paid ~2 ms for its ~30k samples.
  const gpu::BufferRange total = batch.total();
  limited_.begin(rec, &total, capacity, chunkRows_, {kPointsLocal});
  PointsPush p{{box.min[0], box.min[1], box.min[2], 0}, {box.max[0], box.max[1], box.max[2], 0}, chunkRows_, 0,
               midpoints ? 1u : 0u};
  for (uint32_t c = 0; uint64_t(c) * chunkRows_ < capacity; ++c)
    gpu::dispatchLimited(rec, kernel_, {rays, samples, sampleRay, positions, directions}, p, limited_.rows(c, 0),
                         0, "march_points");
}

}  // namespace vknerf::nerf

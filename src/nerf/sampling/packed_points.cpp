#include "nerf/sampling/packed_points.h"

#include <string>

#include "nerf/sampling/packed_layout.h"
#include "nerf/sampling/sample_layout.h"
#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {

struct PointsPush {
  float boxMin[4], boxMax[4];
};

constexpr uint32_t kPointsLocal = 64;  // march_points.comp

using gpu::requireBytes;

}  // namespace

PackedSamplePoints::PackedSamplePoints(Context& ctx)
    : kernel_(ctx, {gpu::shaders::march_points,
                    {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                     gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(PointsPush), {}}) {}

void PackedSamplePoints::record(gpu::Recorder& rec, uint32_t capacity, const gpu::BufferRange& rays,
                                const gpu::BufferRange& samples, const gpu::BufferRange& sampleRay,
                                const gpu::BufferRange& totals, const Aabb& box, const gpu::BufferRange& positions,
                                const gpu::BufferRange& directions) {
  for (int k = 0; k < 3; ++k)
    if (!(box.max[k] > box.min[k])) throw Error("PackedSamplePoints: scene box is empty along axis " + std::to_string(k));
  requireBytes("PackedSamplePoints", "samples", samples, uint64_t(capacity) * kSampleBytes);
  requireBytes("PackedSamplePoints", "sampleRay", sampleRay, uint64_t(capacity) * 4);
  requireBytes("PackedSamplePoints", "totals", totals, PackedLayout::kTotalsBytes);
  requireBytes("PackedSamplePoints", "positions", positions, uint64_t(capacity) * 16);
  requireBytes("PackedSamplePoints", "directions", directions, uint64_t(capacity) * 16);
  PointsPush p{{box.min[0], box.min[1], box.min[2], 0}, {box.max[0], box.max[1], box.max[2], 0}};
  rec.dispatchFlat(kernel_, {rays, samples, sampleRay, totals, positions, directions}, p, capacity, kPointsLocal,
                   "march_points");
}

}  // namespace vknerf::nerf

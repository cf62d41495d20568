#include "nerf/sampling/points.h"

#include <string>

#include "vknerf/error.h"
#include "sampling/sample_points_shared.h"

namespace vknerf::nerf {
namespace {
using Push = glsl::SamplePointsPush;
constexpr uint32_t kLocal = 64;
}  // namespace

SamplePoints::SamplePoints(Context& ctx)
    : kernel_(ctx, {gpu::shaders::sample_points,
                    {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(Push),
                    {}}) {}

void SamplePoints::record(gpu::Recorder& rec, const RaySpan& rays, const gpu::BufferRange& samples,
                          uint32_t samplesPerRay, const Aabb& box, const PointBuffers& out) {
  uint64_t count = uint64_t(rays.count) * samplesPerRay;
  if (count > UINT32_MAX) throw Error("SamplePoints: " + std::to_string(count) + " samples exceed 2^32");
  requireBoxNotEmpty("SamplePoints", box);
  Push p{{box.min[0], box.min[1], box.min[2], 0}, {box.max[0], box.max[1], box.max[2], 0}, uint32_t(count), samplesPerRay};
  rec.dispatchFlat(kernel_, {rays.range, samples, out.positions, out.directions}, p, count, kLocal, "sample_points");
}

}  // namespace vknerf::nerf

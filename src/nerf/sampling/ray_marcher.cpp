#include "nerf/sampling/ray_marcher.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "nerf/rays/rays.h"
#include "nerf/sampling/point_buffers.h"
#include "nerf/sampling/sample_layout.h"
#include "vknerf/error.h"
#include "sampling/march_compact_shared.h"
#include "sampling/march_shared.h"

namespace vknerf::nerf {
namespace {

using glsl::MarchCompactPush;
using glsl::MarchPush;

constexpr uint32_t kMarchLocal = 32;  // march_count, march_write, march_slots, march_compact

using gpu::requireBytes;

}  // namespace

RayMarcher::RayMarcher(Context& ctx, uint32_t maxRays, uint32_t slotSamples)
    : maxRays_(maxRays),
      layout_(ctx, maxRays),
      count_(ctx, {gpu::shaders::march_count,
                   {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                   sizeof(MarchPush), {}}),
      write_(ctx, {gpu::shaders::march_write,
                   {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                    gpu::Binding::Storage, gpu::Binding::Storage},
                   sizeof(MarchPush), {}}) {
  if (!slotSamples) return;
  slots_.emplace(gpu::Buffer::zeros(ctx, VkDeviceSize(slotSamples) * kSampleBytes, "the march's slots"));
  slotsKernel_ = std::make_unique<gpu::Kernel>(
      ctx, gpu::KernelDesc{gpu::shaders::march_slots,
                           {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                            gpu::Binding::Storage},
                           sizeof(MarchPush), {}});
  compact_ = std::make_unique<gpu::Kernel>(
      ctx, gpu::KernelDesc{gpu::shaders::march_compact,
                           {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                            gpu::Binding::Storage},
                           sizeof(MarchCompactPush), {}});
}

float RayMarcher::defaultStep(const Aabb& box) {
  double s = 0;
  for (int k = 0; k < 3; ++k) s += double(box.max[k] - box.min[k]) * (box.max[k] - box.min[k]);
  return float(std::sqrt(s) / 1024.0);
}

Aabb RayMarcher::innerCube(const Aabb& box, uint32_t cascades) {
  const float shrink = std::ldexp(1.0f, -int(cascades - 1));
  Aabb inner;
  for (int k = 0; k < 3; ++k) {
    const float centre = 0.5f * (box.min[k] + box.max[k]), half = 0.5f * (box.max[k] - box.min[k]) * shrink;
    inner.min[k] = centre - half;
    inner.max[k] = centre + half;
  }
  return inner;
}

float RayMarcher::diagonal(const Aabb& b) {
  float s = 0;
  for (int k = 0; k < 3; ++k) s += (b.max[k] - b.min[k]) * (b.max[k] - b.min[k]);
  return std::sqrt(s);
}

void RayMarcher::record(gpu::Recorder& rec, const RaySpan& raySpan, const OccupancyGrid& grid, const Aabb& box,
                        const MarchSteps& steps, const PackedSamples& out) {
  const uint32_t numRays = raySpan.count, maxSamplesPerRay = steps.maxSamplesPerRay;
  const gpu::BufferRange& rays = raySpan.range;
  const float dt = steps.dt;
  const ConeSteps& cone = steps.cone;
  const gpu::BufferRange &offsets = out.offsets, &samples = out.samples, &sampleRay = out.sampleRay,
                         &totals = out.totals;
  if (numRays > maxRays_)
    throw Error("RayMarcher: " + std::to_string(numRays) + " rays exceed the capacity " + std::to_string(maxRays_));
  if (!(std::isfinite(dt) && dt > 0.0f)) throw Error("RayMarcher: step " + std::to_string(dt) + " must be finite and > 0");
  if (maxSamplesPerRay == 0) throw Error("RayMarcher: maxSamplesPerRay must be at least 1");
  if (uint64_t(numRays) * maxSamplesPerRay > 0xffffffffull)
    throw Error("RayMarcher: " + std::to_string(numRays) + " rays x " + std::to_string(maxSamplesPerRay) +
                " samples overflow 32-bit offsets; lower the cap or split the batch");
  requireBoxNotEmpty("RayMarcher", box);
  requireBytes("RayMarcher", "rays", rays, uint64_t(numRays) * kRayBytes);
  PackedLayout::requireOutputs("RayMarcher", numRays, offsets, totals);
  uint64_t capacity = std::min<uint64_t>({gpu::boundBytes(samples) / kSampleBytes, gpu::boundBytes(sampleRay) / 4, 0xffffffffull});

  const uint32_t r = grid.resolution(), cascades = grid.cascades();
  if (cascades > 1 && !(std::isfinite(cone.coneAngle) && cone.coneAngle >= 0.0f && cone.dtMax >= dt && std::isfinite(cone.dtMax)))
    throw Error("RayMarcher: cone angle " + std::to_string(cone.coneAngle) + " must be finite and >= 0, and the largest step " +
                std::to_string(cone.dtMax) + " finite and >= the step " + std::to_string(dt));
  if (cascades > 1 && !(std::isfinite(cone.stepOpacity) && cone.stepOpacity >= 0.0f && cone.stretch >= 1 &&
                        cone.stretch <= kMaxStretch))
    throw Error("RayMarcher: step opacity " + std::to_string(cone.stepOpacity) + " must be finite and >= 0, and the stretch " +
                std::to_string(cone.stretch) + " in [1, " + std::to_string(kMaxStretch) + "]");
  // The grid coordinates are cascade 0's: the inner cube's (the box itself for one cascade).
  const Aabb g = cascades > 1 ? innerCube(box, cascades) : box;
  MarchPush p{{g.min[0], g.min[1], g.min[2], dt},
              {float(r) / (g.max[0] - g.min[0]), float(r) / (g.max[1] - g.min[1]), float(r) / (g.max[2] - g.min[2]), 0},
              numRays, r, maxSamplesPerRay, steps.seed, steps.jitter ? 1u : 0u, uint32_t(capacity), cascades,
              cone.coneAngle, cone.dtMax, cascades > 1 ? cone.stepOpacity : 0.0f, std::max(cone.stretch, 1u)};
  const uint64_t slots = uint64_t(numRays) * maxSamplesPerRay;
  if (slots_ && slots * kSampleBytes <= slots_->size()) {
    // One march into each ray's own slots, then packed: the same batch as the two passes below.
    rec.dispatchFlat(*slotsKernel_, {rays, grid.bits(), layout_.counts(), *slots_, grid.density()}, p, numRays,
                     kMarchLocal, "march_slots");
    layout_.recordOffsetsAndTotals(rec, numRays, uint32_t(capacity), offsets, totals);
    if (capacity > 0)
      rec.dispatchFlat(*compact_, {layout_.counts(), offsets, *slots_, samples, sampleRay},
                       MarchCompactPush{numRays, maxSamplesPerRay}, numRays, kMarchLocal, "march_compact");
    return;
  }
  rec.dispatchFlat(count_, {rays, grid.bits(), layout_.counts(), grid.density()}, p, numRays, kMarchLocal, "march_count");
  layout_.recordOffsetsAndTotals(rec, numRays, uint32_t(capacity), offsets, totals);
  if (capacity > 0)
    rec.dispatchFlat(write_, {rays, grid.bits(), offsets, samples, sampleRay, grid.density()}, p, numRays, kMarchLocal,
                     "march_write");
}

}  // namespace vknerf::nerf

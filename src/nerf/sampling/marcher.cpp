#include "nerf/sampling/marcher.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "nerf/rays/rays.h"
#include "nerf/sampling/sample_layout.h"
#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {

struct BlocksPush {
  uint32_t inputCount, outputCount, clampTo, writeBlockSums;
};
struct AddPush {
  uint32_t outputCount, clampTo;
};
struct MarchPush {
  float boxMin[4];     // w = dt
  float gridScale[4];
  uint32_t numRays, resolution, maxSamples, seed, jitter, capacity;
};
struct TotalsPush {
  uint32_t numRays, localSize, maxGroupsX;
};

constexpr uint32_t kScanBlock = 1024, kAddLocal = 256, kMarchLocal = 32;

using gpu::requireBytes;

struct TruncatePush {
  uint32_t numRays;
  float maxOpticalDepth;
};
struct CompactPush {
  uint32_t numRays;
};
struct PointsPush {
  float boxMin[4], boxMax[4];
};

gpu::KernelDesc totalsKernel() {
  return {gpu::shaders::march_totals, {gpu::Binding::Storage, gpu::Binding::Storage}, sizeof(TotalsPush), {}};
}

void recordTotalsWith(Context& ctx, gpu::Recorder& rec, gpu::Kernel& k, const gpu::BufferRange& offsets,
                      uint32_t numRays, uint32_t localSize, const gpu::BufferRange& totals) {
  if (localSize == 0) throw Error("RayMarcher: dispatch local size must be at least 1");
  requireBytes("RayMarcher", "offsets", offsets, (uint64_t(numRays) + 1) * 4);
  requireBytes("RayMarcher", "totals", totals, RayMarcher::kTotalsBytes);
  TotalsPush p{numRays, localSize, ctx.properties().limits.maxComputeWorkGroupCount[0]};
  rec.dispatch(k, {offsets, totals}, p, 1, 1, 1, "march_totals");
}

uint32_t blocksFor(uint32_t n) { return (n + kScanBlock - 1) / kScanBlock; }

}  // namespace

// ---- PrefixSum ----

PrefixSum::PrefixSum(Context& ctx, uint32_t maxCount)
    : maxCount_(maxCount),
      dummy_(ctx, 16),
      blocks_(ctx, {gpu::shaders::scan_blocks, {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(BlocksPush), {}}),
      add_(ctx, {gpu::shaders::scan_add, {gpu::Binding::Storage, gpu::Binding::Storage}, sizeof(AddPush), {}}) {
  // scan_add covers a level with one x-dispatch of 256-wide groups.
  uint64_t maxAdd = uint64_t(ctx.properties().limits.maxComputeWorkGroupCount[0]) * kAddLocal;
  if (maxCount > maxAdd)
    throw Error("PrefixSum: " + std::to_string(maxCount) + " elements exceed one dispatch (" + std::to_string(maxAdd) + ")");
  for (uint32_t n = blocksFor(maxCount); n > 1; n = blocksFor(n)) {
    blockSums_.emplace_back(ctx, VkDeviceSize(n) * 4);
    blockOffsets_.emplace_back(ctx, VkDeviceSize(n) * 4);
  }
}

void PrefixSum::record(gpu::Recorder& rec, const gpu::BufferRange& input, uint32_t inputCount,
                       const gpu::BufferRange& output, uint32_t outputCount, uint32_t clampTo) {
  if (outputCount > maxCount_)
    throw Error("PrefixSum: " + std::to_string(outputCount) + " outputs exceed the capacity " + std::to_string(maxCount_));
  requireBytes("PrefixSum", "input", input, uint64_t(inputCount) * 4);
  requireBytes("PrefixSum", "output", output, uint64_t(outputCount) * 4);
  recordLevel(rec, input, inputCount, output, outputCount, clampTo, 0);
}

// One block: scanned and clamped in place. More: block totals, their scan (recursively), and the
// scanned totals added back, clamping only there, where the sums are final.
void PrefixSum::recordLevel(gpu::Recorder& rec, const gpu::BufferRange& input, uint32_t inputCount,
                            const gpu::BufferRange& output, uint32_t outputCount, uint32_t clampTo, size_t level) {
  uint32_t blocks = blocksFor(outputCount);
  if (blocks <= 1) {
    BlocksPush p{inputCount, outputCount, clampTo, 0};
    rec.dispatch(blocks_, {input, output, dummy_}, p, blocks, 1, 1, "scan_blocks");
    return;
  }
  BlocksPush p{inputCount, outputCount, 0xffffffffu, 1};
  rec.dispatch(blocks_, {input, output, blockSums_[level]}, p, blocks, 1, 1, "scan_blocks");
  recordLevel(rec, blockSums_[level], blocks, blockOffsets_[level], blocks, 0xffffffffu, level + 1);
  AddPush a{outputCount, clampTo};
  rec.dispatch(add_, {output, blockOffsets_[level]}, a, gpu::groupsFor(outputCount, kAddLocal), 1, 1, "scan_add");
}

// ---- RayMarcher ----

RayMarcher::RayMarcher(Context& ctx, uint32_t maxRays)
    : ctx_(ctx),
      maxRays_(maxRays),
      counts_(ctx, VkDeviceSize(std::max(maxRays, 1u)) * 4),
      scan_(ctx, maxRays + 1),
      count_(ctx, {gpu::shaders::march_count, {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                   sizeof(MarchPush), {}}),
      write_(ctx, {gpu::shaders::march_write,
                   {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                    gpu::Binding::Storage},
                   sizeof(MarchPush), {}}),
      totals_(ctx, totalsKernel()) {}

float RayMarcher::defaultStep(const Aabb& box) {
  double s = 0;
  for (int k = 0; k < 3; ++k) s += double(box.max[k] - box.min[k]) * (box.max[k] - box.min[k]);
  return float(std::sqrt(s) / 1024.0);
}

void RayMarcher::record(gpu::Recorder& rec, const gpu::BufferRange& rays, uint32_t numRays, const OccupancyGrid& grid,
                        const Aabb& box, float dt, uint32_t maxSamplesPerRay, uint32_t seed, bool jitter,
                        const gpu::BufferRange& offsets, const gpu::BufferRange& samples,
                        const gpu::BufferRange& sampleRay, const gpu::BufferRange& totals) {
  if (numRays > maxRays_)
    throw Error("RayMarcher: " + std::to_string(numRays) + " rays exceed the capacity " + std::to_string(maxRays_));
  if (!(std::isfinite(dt) && dt > 0.0f)) throw Error("RayMarcher: step " + std::to_string(dt) + " must be finite and > 0");
  if (maxSamplesPerRay == 0) throw Error("RayMarcher: maxSamplesPerRay must be at least 1");
  if (uint64_t(numRays) * maxSamplesPerRay > 0xffffffffull)
    throw Error("RayMarcher: " + std::to_string(numRays) + " rays x " + std::to_string(maxSamplesPerRay) +
                " samples overflow 32-bit offsets; lower the cap or split the batch");
  for (int k = 0; k < 3; ++k)
    if (!(box.max[k] > box.min[k])) throw Error("RayMarcher: scene box is empty along axis " + std::to_string(k));
  requireBytes("RayMarcher", "rays", rays, uint64_t(numRays) * kRayBytes);
  requireBytes("RayMarcher", "offsets", offsets, (uint64_t(numRays) + 1) * 4);
  requireBytes("RayMarcher", "totals", totals, kTotalsBytes);
  uint64_t capacity = std::min<uint64_t>({gpu::boundBytes(samples) / kSampleBytes, gpu::boundBytes(sampleRay) / 4, 0xffffffffull});

  uint32_t r = grid.resolution();
  MarchPush p{{box.min[0], box.min[1], box.min[2], dt},
              {float(r) / (box.max[0] - box.min[0]), float(r) / (box.max[1] - box.min[1]),
               float(r) / (box.max[2] - box.min[2]), 0},
              numRays, r, maxSamplesPerRay, seed, jitter ? 1u : 0u, uint32_t(capacity)};
  rec.dispatchFlat(count_, {rays, grid.bits(), counts_}, p, numRays, kMarchLocal, "march_count");
  scan_.record(rec, counts_, numRays, offsets, numRays + 1, uint32_t(capacity));
  if (capacity > 0)
    rec.dispatchFlat(write_, {rays, grid.bits(), offsets, samples, sampleRay}, p, numRays, kMarchLocal, "march_write");
  recordTotals(rec, offsets, numRays, kIndirectLocal, totals);
}

void RayMarcher::recordTotals(gpu::Recorder& rec, const gpu::BufferRange& offsets, uint32_t numRays,
                              uint32_t localSize, const gpu::BufferRange& totals) {
  recordTotalsWith(ctx_, rec, totals_, offsets, numRays, localSize, totals);
}

// ---- PackedSamplePoints ----

PackedSamplePoints::PackedSamplePoints(Context& ctx)
    : ctx_(ctx),
      kernel_(ctx, {gpu::shaders::march_points,
                    {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage,
                     gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(PointsPush), {}}) {}

void PackedSamplePoints::record(gpu::Recorder& rec, const gpu::BufferRange& rays, const gpu::BufferRange& samples,
                                const gpu::BufferRange& sampleRay, const gpu::BufferRange& totals, uint32_t capacity,
                                const Aabb& box, const gpu::BufferRange& positions,
                                const gpu::BufferRange& directions) {
  for (int k = 0; k < 3; ++k)
    if (!(box.max[k] > box.min[k])) throw Error("PackedSamplePoints: scene box is empty along axis " + std::to_string(k));
  requireBytes("PackedSamplePoints", "samples", samples, uint64_t(capacity) * kSampleBytes);
  requireBytes("PackedSamplePoints", "sampleRay", sampleRay, uint64_t(capacity) * 4);
  requireBytes("PackedSamplePoints", "totals", totals, RayMarcher::kTotalsBytes);
  requireBytes("PackedSamplePoints", "positions", positions, uint64_t(capacity) * 16);
  requireBytes("PackedSamplePoints", "directions", directions, uint64_t(capacity) * 16);
  PointsPush p{{box.min[0], box.min[1], box.min[2], 0}, {box.max[0], box.max[1], box.max[2], 0}};
  rec.dispatchFlat(kernel_, {rays, samples, sampleRay, totals, positions, directions}, p, capacity, 64, "march_points");
}

// ---- EarlyTermination ----

EarlyTermination::EarlyTermination(Context& ctx, uint32_t maxRays)
    : ctx_(ctx),
      maxRays_(maxRays),
      kept_(ctx, VkDeviceSize(std::max(maxRays, 1u)) * 4),
      scan_(ctx, maxRays + 1),
      truncate_(ctx, {gpu::shaders::march_truncate,
                      {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                      sizeof(TruncatePush), {}}),
      compact_(ctx, {gpu::shaders::march_compact, std::vector<gpu::Binding>(8, gpu::Binding::Storage), sizeof(CompactPush), {}}),
      totals_(ctx, totalsKernel()) {}

float EarlyTermination::maxOpticalDepth(float minTransmittance) { return float(-std::log(double(minTransmittance))); }

void EarlyTermination::record(gpu::Recorder& rec, uint32_t numRays, const gpu::BufferRange& offsets,
                              const gpu::BufferRange& samples, const gpu::BufferRange& sampleRay,
                              const gpu::BufferRange& field, float minTransmittance,
                              const gpu::BufferRange& outOffsets, const gpu::BufferRange& outSamples,
                              const gpu::BufferRange& outSampleRay, const gpu::BufferRange& outField,
                              const gpu::BufferRange& outTotals) {
  if (numRays > maxRays_)
    throw Error("EarlyTermination: " + std::to_string(numRays) + " rays exceed the capacity " + std::to_string(maxRays_));
  if (!(minTransmittance > 0.0f && minTransmittance <= 1.0f))
    throw Error("EarlyTermination: minTransmittance " + std::to_string(minTransmittance) + " is outside (0, 1]");
  requireBytes("EarlyTermination", "offsets", offsets, (uint64_t(numRays) + 1) * 4);
  requireBytes("EarlyTermination", "out offsets", outOffsets, (uint64_t(numRays) + 1) * 4);
  // The survivors never outnumber the input, so outputs as large as the inputs always suffice;
  // smaller ones clamp like the marcher's (the last rays lose samples).
  uint64_t capacity = std::min<uint64_t>({gpu::boundBytes(outSamples) / kSampleBytes, gpu::boundBytes(outSampleRay) / 4,
                                          gpu::boundBytes(outField) / 16, 0xffffffffull});
  TruncatePush tp{numRays, maxOpticalDepth(minTransmittance)};
  rec.dispatchFlat(truncate_, {offsets, samples, field, kept_}, tp, numRays, kMarchLocal, "march_truncate");
  scan_.record(rec, kept_, numRays, outOffsets, numRays + 1, uint32_t(capacity));
  CompactPush cp{numRays};
  if (capacity > 0)
    rec.dispatchFlat(compact_, {offsets, samples, sampleRay, field, outOffsets, outSamples, outSampleRay, outField}, cp,
                     numRays, kMarchLocal, "march_compact");
  recordTotalsWith(ctx_, rec, totals_, outOffsets, numRays, RayMarcher::kIndirectLocal, outTotals);
}

}  // namespace vknerf::nerf

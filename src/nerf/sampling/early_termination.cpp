#include "nerf/sampling/early_termination.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "nerf/sampling/sample_layout.h"
#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {

struct TruncatePush {
  uint32_t numRays;
  float maxOpticalDepth;
};
struct CompactPush {
  uint32_t numRays;
};

constexpr uint32_t kRayLocal = 32;  // march_truncate.comp, march_compact.comp

using gpu::requireBytes;

}  // namespace

EarlyTermination::EarlyTermination(Context& ctx, uint32_t maxRays)
    : maxRays_(maxRays),
      layout_(ctx, maxRays),
      truncate_(ctx, {gpu::shaders::march_truncate,
                      {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                      sizeof(TruncatePush), {}}),
      compact_(ctx, {gpu::shaders::march_compact, std::vector<gpu::Binding>(8, gpu::Binding::Storage), sizeof(CompactPush), {}}) {}

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
  PackedLayout::requireOutputs("EarlyTermination out", numRays, outOffsets, outTotals);
  // The survivors never outnumber the input, so outputs as large as the inputs always suffice;
  // smaller ones clamp like the marcher's (the last rays lose samples).
  uint64_t capacity = std::min<uint64_t>({gpu::boundBytes(outSamples) / kSampleBytes, gpu::boundBytes(outSampleRay) / 4,
                                          gpu::boundBytes(outField) / 16, 0xffffffffull});
  TruncatePush tp{numRays, maxOpticalDepth(minTransmittance)};
  rec.dispatchFlat(truncate_, {offsets, samples, field, layout_.counts()}, tp, numRays, kRayLocal, "march_truncate");
  layout_.recordOffsetsAndTotals(rec, numRays, uint32_t(capacity), outOffsets, outTotals);
  CompactPush cp{numRays};
  if (capacity > 0)
    rec.dispatchFlat(compact_, {offsets, samples, sampleRay, field, outOffsets, outSamples, outSampleRay, outField}, cp,
                     numRays, kRayLocal, "march_compact");
}

}  // namespace vknerf::nerf

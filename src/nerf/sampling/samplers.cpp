#include "nerf/sampling/samplers.h"

#include <cmath>
#include <string>

#include "nerf/rays/rays.h"
#include "vknerf/error.h"
#include "sampling/sample_stratified_shared.h"
#include "sampling/sample_pdf_shared.h"
#include "sampling/sampling_shared.h"

namespace vknerf::nerf {
namespace {

using glsl::StratifiedPush;
using glsl::PdfPush;

// One invocation per ray in both kernels: small groups so that a few thousand rays still make
// enough workgroups (one lavapipe task each) to spread over the worker threads.
constexpr uint32_t kStratifiedLocal = 32;
constexpr uint32_t kPdfLocal = 32;

using gpu::requireBytes;

void requireIndexable(const char* stage, uint64_t count) {
  if (count > 0xffffffffull)
    throw Error(std::string(stage) + ": " + std::to_string(count) + " samples in one batch overflow 32-bit indices; split the batch");
}

}  // namespace

StratifiedSampler::StratifiedSampler(Context& ctx)
    : kernel_(ctx, {gpu::shaders::sample_stratified, {gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(StratifiedPush),
                    {{glsl::SamplingSpec::LOCAL_SIZE_X, kStratifiedLocal}}}) {}

void StratifiedSampler::record(gpu::Recorder& rec, const RaySpan& raySpan, uint32_t samplesPerRay,
                               const Jitter& jitter, const gpu::BufferRange& samples) {
  const uint32_t numRays = raySpan.count;
  const gpu::BufferRange& rays = raySpan.range;
  uint64_t count = uint64_t(numRays) * samplesPerRay;
  requireIndexable("sample_stratified", count);
  requireBytes("sample_stratified", "rays", rays, uint64_t(numRays) * kRayBytes);
  requireBytes("sample_stratified", "samples", samples, count * kSampleBytes);
  StratifiedPush p{numRays, samplesPerRay, jitter.seed, jitter.jitter ? 1u : 0u};
  rec.dispatchFlat(kernel_, {rays, samples}, p, numRays, kStratifiedLocal, "sample_stratified");
}

PdfSampler::PdfSampler(Context& ctx)
    : kernel_(ctx, {gpu::shaders::sample_pdf,
                    {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(PdfPush),
                    {{glsl::SamplingSpec::LOCAL_SIZE_X, kPdfLocal}}}) {}

void PdfSampler::record(gpu::Recorder& rec, const RaySpan& raySpan, const CoarseSamples& coarse, const Draws& draws,
                        const gpu::BufferRange& mergedSamples) {
  const uint32_t numRays = raySpan.count, nCoarse = coarse.perRay, nFine = draws.perRay;
  const gpu::BufferRange &rays = raySpan.range, &coarseSamples = coarse.samples, &coarseWeights = coarse.weights;
  const float padding = draws.padding;
  if (!(std::isfinite(padding) && padding >= 0.0f))
    throw Error("sample_pdf: padding " + std::to_string(padding) + " must be finite and >= 0");
  uint64_t perRay = uint64_t(nCoarse) + nFine;
  requireIndexable("sample_pdf", uint64_t(numRays) * perRay);
  requireBytes("sample_pdf", "rays", rays, uint64_t(numRays) * kRayBytes);
  requireBytes("sample_pdf", "coarse samples", coarseSamples, uint64_t(numRays) * nCoarse * kSampleBytes);
  requireBytes("sample_pdf", "coarse weights", coarseWeights, uint64_t(numRays) * nCoarse * sizeof(float));
  requireBytes("sample_pdf", "merged samples", mergedSamples, uint64_t(numRays) * perRay * kSampleBytes);
  PdfPush p{numRays, nCoarse, nFine, draws.jitter.seed, draws.jitter.jitter ? 1u : 0u, padding};
  rec.dispatchFlat(kernel_, {rays, coarseSamples, coarseWeights, mergedSamples}, p, numRays, kPdfLocal, "sample_pdf");
}

}  // namespace vknerf::nerf

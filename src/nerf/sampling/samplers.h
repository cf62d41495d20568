#pragma once
// Stage 2 of the data flow: samples along the rays (shaders/sampling/sample_stratified.comp for the coarse
// pass, shaders/sampling/sample_pdf.comp for the fine pass of hierarchical sampling).
// Layout: a sample is vec2(t, delta). Within a ray samples are sorted by t, delta_i = t_{i+1} - t_i
// and the last delta closes at the ray's t_far (bounded sampling, no 1e10 sentinel). Fixed count
// per ray: ray r owns samples [r*N, (r+1)*N). A ray that misses (t_near < 0) or has no length gets
// all samples (max(t_near, 0), 0): zero deltas composite to the background with zero gradients.
// The RNG of ray r is keyed by (seed, r, sample index): give the coarse and fine passes of one step
// different seeds so their jitter is independent.
#include <cstdint>

#include "nerf/sampling/sample_layout.h"
#include "gpu/kernel.h"
#include "gpu/recorder.h"

namespace vknerf::nerf {



class StratifiedSampler {
 public:
  explicit StratifiedSampler(Context& ctx);
  // samplesPerRay equal bins in [t_near, t_far] of each ray, one sample per bin: at
  // t_near + (i + u) / N * (t_far - t_near) with u = rng01(seed, ray, i) (jitter) or 0.5.
  // `samples` holds numRays * samplesPerRay samples.
  void record(gpu::Recorder& rec, uint32_t numRays, const gpu::BufferRange& rays, uint32_t samplesPerRay, uint32_t seed,
              bool jitter, const gpu::BufferRange& samples);

 private:
  gpu::Kernel kernel_;
};

class PdfSampler {
 public:
  explicit PdfSampler(Context& ctx);
  // nFine inverse-CDF draws per ray from the coarse weights (nCoarse floats per ray, each clamped at
  // 0 and plus `padding`), whose bins are the coarse segments [t_k, t_{k+1}], the last closing at
  // t_far (only the coarse t's are read). Uniform over [t_near, t_far] instead when the weights sum
  // below 1e-30 (or to Inf/NaN) or the coarse segments have no length. Draw j is at
  // u = (j + rng01(seed, ray, j)) / nFine (jitter) or (j + 0.5) / nFine, placed by linear
  // interpolation in its bin. The fine t's are merged in order with the coarse ones: `mergedSamples`
  // holds numRays * (nCoarse + nFine) samples, deltas recomputed. Throws vknerf::Error for a
  // negative or non-finite padding or a buffer too small for the counts.
  void record(gpu::Recorder& rec, uint32_t numRays, const gpu::BufferRange& rays, const gpu::BufferRange& coarseSamples,
              const gpu::BufferRange& coarseWeights, uint32_t nCoarse, uint32_t nFine, uint32_t seed, bool jitter,
              float padding, const gpu::BufferRange& mergedSamples);

 private:
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

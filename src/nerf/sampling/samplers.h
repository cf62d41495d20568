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

#include "nerf/rays/rays.h"
#include "nerf/sampling/sample_layout.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"

namespace vknerf::nerf {

// Jittered draws: u = rng01(seed, ray, i) when `jitter`, else the bin's middle.
struct Jitter {
  uint32_t seed = 0;
  bool jitter = false;
};

// The coarse pass a fine pass draws from: `perRay` samples per ray and their compositing weights.
struct CoarseSamples {
  gpu::BufferRange samples, weights;
  uint32_t perRay = 0;
};

class StratifiedSampler {
 public:
  explicit StratifiedSampler(Context& ctx);
  // samplesPerRay equal bins in [t_near, t_far] of each ray, one sample per bin: at
  // t_near + (i + u) / N * (t_far - t_near) with u = rng01(seed, ray, i) (jitter) or 0.5.
  // `samples` holds rays.count * samplesPerRay samples.
  void record(gpu::Recorder& rec, const RaySpan& rays, uint32_t samplesPerRay, const Jitter& jitter,
              const gpu::BufferRange& samples);

 private:
  gpu::Kernel kernel_;
};

class PdfSampler {
 public:
  explicit PdfSampler(Context& ctx);
  // How the fine pass draws: perRay (nFine) draws per ray, each coarse weight plus `padding`.
  struct Draws {
    uint32_t perRay = 0;
    Jitter jitter;
    float padding = 0;
  };
  // nFine inverse-CDF draws per ray from the coarse weights (nCoarse = coarse.perRay floats per
  // ray, each clamped at 0 and plus `padding`), whose bins are the coarse segments [t_k, t_{k+1}],
  // the last closing at t_far (only the coarse t's are read). Uniform over [t_near, t_far] instead
  // when the weights sum below 1e-30 (or to Inf/NaN) or the coarse segments have no length. Draw j
  // is at u = (j + rng01(seed, ray, j)) / nFine (jitter) or (j + 0.5) / nFine, placed by linear
  // interpolation in its bin. The fine t's are merged in order with the coarse ones: `mergedSamples`
  // holds rays.count * (nCoarse + nFine) samples, deltas recomputed. Throws vknerf::Error for a
  // negative or non-finite padding or a buffer too small for the counts.
  void record(gpu::Recorder& rec, const RaySpan& rays, const CoarseSamples& coarse, const Draws& draws,
              const gpu::BufferRange& mergedSamples);

 private:
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

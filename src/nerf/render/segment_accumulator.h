#pragma once
// A render that marches its rays in segments and stops each where it has become opaque
// (instant-ngp's early termination, for rendering): round by round, each live ray is marched for at
// most `cap` more samples, the field shades them, the compositor composites them over a black
// background from a transmittance of 1 into segmentColor() / segmentDepth(), and record() puts that
// segment behind what the ray gathered before (shaders/render/accumulate_segment.comp). A ray ends
// when its march is done, its transmittance falls below minTransmittance or the round is the last;
// its background is added then. A ray's t_near carries where its next segment starts (-1 once it
// has ended), so every round runs on the device with no host read-back; after a submission, active()
// says how many rays another round must march. Without it, a render shades every sample the march finds,
// also the ~40% of a trained object's that lie behind its surfaces.
#include <cstdint>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/rays/rays.h"
#include "nerf/sampling/packed_samples.h"

namespace vknerf::nerf {

class SegmentAccumulator {
 public:
  SegmentAccumulator(Context& ctx, uint32_t maxRays);

  // The compositor's outputs for one segment: (rgb, opacity) and depth per ray.
  const gpu::Buffer& segmentColor() const { return segmentColor_; }
  const gpu::Buffer& segmentDepth() const { return segmentDepth_; }
  gpu::Buffer& segmentColor() { return segmentColor_; }
  gpu::Buffer& segmentDepth() { return segmentDepth_; }

  // Zeroes the counts active() and samples() read.
  void recordResetCounts(gpu::Recorder& rec);

  struct Round {
    uint32_t cap;       // the most samples the round's march gave a ray
    bool first, last;   // the tile's first round (nothing gathered) / last round (every ray ends)
    float minTransmittance;
  };
  // Per ray of a render: its background, and the colour and depth that gather the render.
  struct Gathered {
    gpu::BufferRange background, color, depth;
  };
  // rays: (o, t_near), (d, t_far) per ray, t_near rewritten; batch: the round's march (its offsets
  // and samples are read).
  void record(gpu::Recorder& rec, const Round& round, const RaySpan& rays, const PackedSamples& batch,
              const Gathered& gathered);

  // After the submission's wait: rays still live after the rounds since recordResetCounts (one
  // round: the rays the next round must march), and the samples those rounds composited.
  uint32_t active() const;
  uint32_t samples() const;

 private:
  uint32_t maxRays_;
  gpu::Buffer segmentColor_, segmentDepth_, counters_;
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

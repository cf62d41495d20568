#pragma once
// Ray marching with empty-space skipping into a packed sample layout (shaders/sampling/march_*.comp).
//
// Samples of ray r are the lattice points t_k = t_near + (u + k) dt, k = 0, 1, ..., with t_k < t_far
// whose occupancy cell is occupied, in order, at most maxSamplesPerRay; u = rng01(seed, r, 0)
// (jitter, training) or 0 (rendering). Each sample is vec2(t_k, min(dt, t_far - t_k)): it stands
// for [t_k, t_k + dt], cut at t_far. Empty cells are skipped in one jump, giving exactly the
// samples of the one-step-at-a-time march (tests/reference/occupancy/occupancy_grid.h, ref::marchRay).
// A grid of several cascades (unbounded scenes) is marched with instant-ngp's cone steps instead:
// dt(t) = clamp(t coneAngle, dt, dtMax), empty cells of every cascade jumped over in whole steps
// (ref::marchRayCascaded); each sample is then (t, min(dt(t), t_far - t)), or n dt(t) for a
// sample stretched through faint cells (ConeSteps::stepOpacity).
// Output layouts:
//   offsets     uint[numRays + 1]: ray r owns samples [off[r], off[r+1]); off[numRays] = total
//               (the packed layout of nerf::Compositor with samplesPerRay = 0)
//   samples     vec2 (t, delta) per sample
//   sampleRay   uint per sample: the ray it belongs to
//   totals      uint[4] as PackedLayout writes them, for PackedLayout::kIndirectLocal
// The sample capacity is what the samples and sampleRay buffers hold; a batch over it keeps the
// samples of its first rays and the offsets are clamped, so off[numRays] <= capacity always.
#include <cstdint>
#include <memory>
#include <optional>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/occupancy/occupancy_grid.h"
#include "nerf/rays/rays.h"
#include "nerf/sampling/packed_layout.h"
#include "nerf/sampling/packed_samples.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

// Step sizes of a cascaded march: the step grows with t up to dtMax (dtMax >= the march's dt).
// stepOpacity > 0 stretches a sample over up to `stretch` steps through cells faint enough that it
// stays at most that optically thick by the grid's running-maximum densities (occupancy.glsl,
// stretchedStep; ref::marchRayCascaded); 0 never stretches.
struct ConeSteps {
  float coneAngle = 0, dtMax = 0;
  float stepOpacity = 0;
  uint32_t stretch = 1;
};

// How one march steps along its rays: the step dt, at most maxSamplesPerRay samples per ray, the
// jitter's seed when `jitter` (training), and the cone steps (used only with several cascades).
struct MarchSteps {
  float dt = 0;
  uint32_t maxSamplesPerRay = 0;
  uint32_t seed = 0;
  bool jitter = false;
  ConeSteps cone = {};
};

class RayMarcher {
 public:
  // slotSamples > 0: a buffer of that many samples lets a batch whose rays x maxSamplesPerRay fit
  // it march once (march_slots, then march_compact) instead of twice (march_count, march_write):
  // a render's block, whose rays have room for all their samples. The batch is the same.
  RayMarcher(Context& ctx, uint32_t maxRays, uint32_t slotSamples = 0);

  // The most cone steps one stretched sample may stand for: each costs the march a cell lookup.
  static constexpr uint32_t kMaxStretch = 64;

  // instant-ngp's step for a bounded scene: the box diagonal over 1024.
  static float defaultStep(const Aabb& box);

  // rays: 2 x vec4 per ray (o, t_near), (d, t_far), misses (-1, -1). Throws vknerf::Error for
  // rays.count > maxRays, steps.dt not finite and > 0, steps.maxSamplesPerRay == 0, rays.count *
  // maxSamplesPerRay over 32 bits, an empty box, or outputs too small for the rays (offsets,
  // totals); with cascades, a cone angle not finite and >= 0, dtMax < dt, a step opacity not finite
  // and >= 0, or a stretch outside [1, kMaxStretch]. `box` is the whole scene
  // box (the outermost cascade's).
  void record(gpu::Recorder& rec, const RaySpan& rays, const OccupancyGrid& grid, const Aabb& box,
              const MarchSteps& steps, const PackedSamples& out);

  // After record() at a sample capacity: the batch cut to its whole rays on the device, the rays kept
  // written to `wholeRays` (PackedLayout::recordCutToWholeRays).
  void recordCutToWholeRays(gpu::Recorder& rec, const PackedCut& cut, const PackedSamples& batch,
                            const gpu::BufferRange& wholeRays) {
    layout_.recordCutToWholeRays(rec, cut, batch, wholeRays);
  }

  // The inner cube of a grid of `cascades` over `box`: the box shrunk by 2^(cascades - 1) about its centre.
  static Aabb innerCube(const Aabb& box, uint32_t cascades);
  // A box's diagonal: the march step is the inner cube's over the march steps.
  static float diagonal(const Aabb& box);

 private:
  uint32_t maxRays_;
  PackedLayout layout_;  // counts: the samples each ray marches
  gpu::Kernel count_, write_;
  std::optional<gpu::Buffer> slots_;            // slotSamples samples, each ray's maxSamplesPerRay in a row
  std::unique_ptr<gpu::Kernel> slotsKernel_, compact_;
};

}  // namespace vknerf::nerf

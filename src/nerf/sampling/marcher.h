#pragma once
// Ray marching with empty-space skipping into a packed sample layout (shaders/march_*.comp) and
// the exclusive prefix sum it is built on (shaders/scan_*.comp).
//
// Samples of ray r are the lattice points t_k = t_near + (u + k) dt, k = 0, 1, ..., with t_k < t_far
// whose occupancy cell is occupied, in order, at most maxSamplesPerRay; u = rng01(seed, r, 0)
// (jitter, training) or 0 (rendering). Each sample is vec2(t_k, min(dt, t_far - t_k)): it stands
// for [t_k, t_k + dt], cut at t_far. Empty cells are skipped in one jump, giving exactly the
// samples of the one-step-at-a-time march (src/reference/occupancy.h, ref::marchRay).
// Output layouts:
//   offsets     uint[numRays + 1]: ray r owns samples [off[r], off[r+1]); off[numRays] = total
//               (the packed layout of nerf::Compositor with samplesPerRay = 0)
//   samples     vec2 (t, delta) per sample
//   sampleRay   uint per sample: the ray it belongs to
//   totals      uint[4]: [0] = total samples, [1..3] = a VkDispatchIndirectCommand covering the
//               total with workgroups of kIndirectLocal (x capped at the device limit, the rest in
//               y: per-sample kernels index flatly, as sampling.glsl's flatInvocation() does)
// The sample capacity is what the samples and sampleRay buffers hold; a batch over it keeps the
// samples of its first rays and the offsets are clamped, so off[numRays] <= capacity always.
#include <cstdint>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu/recorder.h"
#include "nerf/occupancy/occupancy_grid.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

// Exclusive prefix sum of uints: out[i] = min(sum_{j<i} in[j], clampTo) for i < outputCount,
// with in[j] = 0 for j >= inputCount (so n counts scanned into n + 1 outputs end with the total).
// Sums must not overflow 32 bits. Scratch for up to maxCount outputs is allocated once.
class PrefixSum {
 public:
  PrefixSum(Context& ctx, uint32_t maxCount);
  void record(gpu::Recorder& rec, const gpu::BufferRange& input, uint32_t inputCount, const gpu::BufferRange& output,
              uint32_t outputCount, uint32_t clampTo = 0xffffffffu);
  uint32_t maxCount() const { return maxCount_; }

 private:
  void recordLevel(gpu::Recorder& rec, const gpu::BufferRange& input, uint32_t inputCount,
                   const gpu::BufferRange& output, uint32_t outputCount, uint32_t clampTo, size_t level);
  uint32_t maxCount_;
  std::vector<gpu::Buffer> blockSums_, blockOffsets_;  // one pair per level above the first
  gpu::Buffer dummy_;
  gpu::Kernel blocks_, add_;
};

class RayMarcher {
 public:
  static constexpr uint32_t kIndirectLocal = 64;
  static constexpr VkDeviceSize kTotalsBytes = 16;

  RayMarcher(Context& ctx, uint32_t maxRays);

  // instant-ngp's step for a bounded scene: the box diagonal over 1024.
  static float defaultStep(const Aabb& box);

  // rays: 2 x vec4 per ray (o, t_near), (d, t_far), misses (-1, -1). Throws vknerf::Error for
  // numRays > maxRays, dt not finite and > 0, maxSamplesPerRay == 0, numRays * maxSamplesPerRay
  // over 32 bits, an empty box, or buffers too small for numRays (offsets, totals).
  void record(gpu::Recorder& rec, const gpu::BufferRange& rays, uint32_t numRays, const OccupancyGrid& grid,
              const Aabb& box, float dt, uint32_t maxSamplesPerRay, uint32_t seed, bool jitter,
              const gpu::BufferRange& offsets, const gpu::BufferRange& samples, const gpu::BufferRange& sampleRay,
              const gpu::BufferRange& totals);

  // totals as record() writes them, from offsets[numRays], with dispatch arguments for `localSize`.
  void recordTotals(gpu::Recorder& rec, const gpu::BufferRange& offsets, uint32_t numRays, uint32_t localSize,
                    const gpu::BufferRange& totals);

 private:
  Context& ctx_;
  uint32_t maxRays_;
  gpu::Buffer counts_;
  PrefixSum scan_;
  gpu::Kernel count_, write_, totals_;
};

// Field inputs of a packed batch (shaders/march_points.comp): positions (normalised box [-1, 1]^3)
// and directions, vec4 with w = 0, one per sample. The count comes from the marcher's totals on
// the device; `capacity` (the samples the output buffers hold) bounds the dispatch.
class PackedSamplePoints {
 public:
  explicit PackedSamplePoints(Context& ctx);
  void record(gpu::Recorder& rec, const gpu::BufferRange& rays, const gpu::BufferRange& samples,
              const gpu::BufferRange& sampleRay, const gpu::BufferRange& totals, uint32_t capacity, const Aabb& box,
              const gpu::BufferRange& positions, const gpu::BufferRange& directions);

 private:
  Context& ctx_;
  gpu::Kernel kernel_;
};

// Early termination of a packed batch once the field is known (shaders/march_truncate.comp,
// march_compact.comp): ray r keeps its samples while the transmittance in front of them is at
// least minTransmittance (default 1e-4), i.e. up to and including the sample where it drops
// below; the survivors are packed into the out* buffers (same layouts as RayMarcher's outputs,
// field vec4 (r, g, b, sigma) per sample, which the compositor takes as it is). The light the
// dropped samples could add is below minTransmittance times their brightest colour.
// It lives here rather than in the compositor so that the backward passes, the expensive part,
// run over the survivors only.
class EarlyTermination {
 public:
  EarlyTermination(Context& ctx, uint32_t maxRays);
  void record(gpu::Recorder& rec, uint32_t numRays, const gpu::BufferRange& offsets, const gpu::BufferRange& samples,
              const gpu::BufferRange& sampleRay, const gpu::BufferRange& field, float minTransmittance,
              const gpu::BufferRange& outOffsets, const gpu::BufferRange& outSamples,
              const gpu::BufferRange& outSampleRay, const gpu::BufferRange& outField, const gpu::BufferRange& outTotals);
  // The optical depth the kernels compare against: -ln(minTransmittance), rounded to float.
  static float maxOpticalDepth(float minTransmittance);

 private:
  Context& ctx_;
  uint32_t maxRays_;
  gpu::Buffer kept_;
  PrefixSum scan_;
  gpu::Kernel truncate_, compact_, totals_;
};

}  // namespace vknerf::nerf

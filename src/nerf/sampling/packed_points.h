#pragma once
// Field inputs of a packed batch (shaders/sampling/march_points.comp): positions (normalised box
// [-1, 1]^3) and directions, vec4 with w = 0, one per sample. The count comes from the batch's
// totals (PackedLayout) on the device, which also sizes the dispatches (indirect, in chunks of
// `chunkRows`); `capacity` (the samples the output buffers hold) bounds them.
#include <cstdint>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/limited_dispatch.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/sampling/packed_samples.h"
#include "nerf/sampling/point_buffers.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

class PackedSamplePoints {
 public:
  // A chunk is at most 32768 workgroups of 64 (the x count every device allows is 65535).
  static constexpr uint32_t kChunkRows = 1u << 21;
  explicit PackedSamplePoints(Context& ctx, uint32_t chunkRows = kChunkRows);
  // rays: those the batch was marched for (its sampleRay indexes them); reads the batch's samples,
  // sampleRay and totals. midpoints: each sample's point is the middle of its interval [t, t +
  // delta] (a sample that stands for several march steps: the proposal's candidates), else t.
  void record(gpu::Recorder& rec, uint32_t capacity, const gpu::BufferRange& rays, const PackedSamples& batch,
              const Aabb& box, const PointBuffers& out, bool midpoints = false);

 private:
  gpu::Kernel kernel_;
  gpu::LimitedDispatch limited_;
  uint32_t chunkRows_;
};

}  // namespace vknerf::nerf

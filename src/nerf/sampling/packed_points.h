#pragma once
// Field inputs of a packed batch (shaders/sampling/march_points.comp): positions (normalised box
// [-1, 1]^3) and directions, vec4 with w = 0, one per sample. The count comes from the batch's
// totals (PackedLayout) on the device, which also sizes the dispatches (indirect, in chunks of
// `chunkRows`); `capacity` (the samples the output buffers hold) bounds them.
#include <cstdint>

#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu/limited_dispatch.h"
#include "gpu/recorder.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

class PackedSamplePoints {
 public:
  // A chunk is at most 32768 workgroups of 64 (the x count every device allows is 65535).
  static constexpr uint32_t kChunkRows = 1u << 21;
  explicit PackedSamplePoints(Context& ctx, uint32_t chunkRows = kChunkRows);
  void record(gpu::Recorder& rec, uint32_t capacity, const gpu::BufferRange& rays, const gpu::BufferRange& samples,
              const gpu::BufferRange& sampleRay, const gpu::BufferRange& totals, const Aabb& box,
              const gpu::BufferRange& positions, const gpu::BufferRange& directions);

 private:
  gpu::Kernel kernel_;
  gpu::LimitedDispatch limited_;
  uint32_t chunkRows_;
};

}  // namespace vknerf::nerf

#pragma once
// Field inputs of a packed batch (shaders/sampling/march_points.comp): positions (normalised box
// [-1, 1]^3) and directions, vec4 with w = 0, one per sample. The count comes from the batch's
// totals (PackedLayout) on the device; `capacity` (the samples the output buffers hold) bounds
// the dispatch.
#include <cstdint>

#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu/recorder.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {

class PackedSamplePoints {
 public:
  explicit PackedSamplePoints(Context& ctx);
  void record(gpu::Recorder& rec, uint32_t capacity, const gpu::BufferRange& rays, const gpu::BufferRange& samples,
              const gpu::BufferRange& sampleRay, const gpu::BufferRange& totals, const Aabb& box,
              const gpu::BufferRange& positions, const gpu::BufferRange& directions);

 private:
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

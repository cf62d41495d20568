#pragma once
// Field inputs of a fixed-layout sample batch (shaders/sampling/sample_points.comp): ray r owns samples
// [r*N, (r+1)*N); each sample (t, delta) becomes a position o + t d mapped from the scene box onto
// [-1, 1]^3 and the ray's unit direction, both written as vec4 with w = 0.
#include "nerf/sampling/sample_layout.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/rays/rays.h"
#include "nerf/sampling/point_buffers.h"
#include "vknerf/camera.h"

namespace vknerf::nerf {


constexpr VkDeviceSize kPointBytes = 16;  // vec4 position or direction

class SamplePoints {
 public:
  explicit SamplePoints(Context& ctx);
  // rays: 2 x vec4 per ray; samples: rays.count * samplesPerRay vec2; out: vec4 per sample.
  void record(gpu::Recorder& rec, const RaySpan& rays, const gpu::BufferRange& samples, uint32_t samplesPerRay,
              const Aabb& box, const PointBuffers& out);

 private:
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

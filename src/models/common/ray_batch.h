#pragma once
// The rays of one batch with their pixel ids and per-ray backgrounds: random pixels of the
// training cameras for a training step, or a block of one view for rendering. Both models use it.
#include <array>
#include <cstdint>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/field_pipeline.h"
#include "nerf/loss/background_colors.h"
#include "nerf/loss/photometric_loss.h"
#include "nerf/rays/rays.h"
#include "nerf/render/composite.h"

namespace vknerf::models {

// The seed of training step `step`: rays, samples and backgrounds of a step all derive from it.
uint32_t stepSeed(const TrainConfig& config, uint32_t step);

class RayBatch {
 public:
  // Rays start `nearPlane` in front of their camera (or at the scene box, whichever is further).
  // inCameraRuns: training batches come in runs of one camera each (RayGeneration::RandomPixels),
  // for a model that sums gradients per training camera.
  RayBatch(Context& ctx, uint32_t capacity, float nearPlane = kNearPlane, bool inCameraRuns = false);

  // `count` rays through random training pixels (seed: stepSeed), with random backgrounds when
  // config.randomBackground, else config.background. A transparent pixel's target is then a random
  // colour, so empty space learns zero density; an opaque pixel's is the pixel whatever the
  // background, so its ray must turn opaque inside the box (instant-ngp's choice for photos without
  // alpha) instead of borrowing the background's colour. A learned far field overwrites these.
  void recordTraining(gpu::Recorder& rec, const TrainingData& data, uint32_t seed, uint32_t count, const Aabb& box,
                      const TrainConfig& config);
  // Rays through the pixels of `view`, clipped to `box`, over its constant background.
  void recordView(gpu::Recorder& rec, const ViewBlock& view, const Aabb& box);

  uint32_t capacity() const { return capacity_; }
  gpu::Buffer& rays() { return rays_; }          // 2 x vec4 per ray (nerf::kRayBytes)
  gpu::Buffer& pixelIds() { return pixelIds_; }  // uvec2 (camera, pixel) per ray
  gpu::Buffer& background() { return background_; }  // vec4 per ray (nerf::kColorBytes)
  const gpu::Buffer& background() const { return background_; }
  // Rays [first, first + count) and their backgrounds, each binding exactly those rays.
  nerf::RaySpan rays(uint32_t first, uint32_t count) { return {gpu::rowsOf(rays_, nerf::kRayBytes, first, count), count}; }
  gpu::BufferRange backgrounds(uint32_t first, uint32_t count) {
    return gpu::rowsOf(background_, nerf::kColorBytes, first, count);
  }

 private:
  uint32_t capacity_;
  float nearPlane_;
  bool inCameraRuns_;
  nerf::RayGeneration generation_;
  nerf::BackgroundColors backgrounds_;
  gpu::Buffer rays_, pixelIds_, background_;
};

}  // namespace vknerf::models

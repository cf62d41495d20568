#pragma once
// The photometric MSE loss with its gradient (shaders/loss/loss_photometric.comp).
// Layouts: background (BackgroundColors) and predictions are one vec4 per ray, pred = (r, g, b,
// opacity); pixel ids are uvec2(camera, pixel within image) per ray; the training images are packed
// RGBA8 (uint per pixel, R in the low byte) in one or more bindings (nerf::TrainingPixels), image c
// in binding cameras[c].size[3] from its pixel cameras[c].size[2] on (CameraGpu); dPred is one vec4 per ray (opacity component 0); partials is one float per
// workgroup of kRaysPerPartial rays: that workgroup's sum of squared errors over rgb.
#include <cstdint>
#include <span>

#include "gpu/kernel.h"
#include "gpu/recorder.h"

namespace vknerf::nerf {

struct LossStats {
  double mse = 0;   // mean over rays and the 3 channels
  double psnr = 0;  // -10 log10(mse), 100 dB for a perfect fit
};

class PhotometricLoss {
 public:
  static constexpr uint32_t kRaysPerPartial = 128;  // the shader's workgroup size
  static constexpr uint32_t kPixelBindings = 8;     // pixel buffers one dispatch binds

  explicit PhotometricLoss(Context& ctx);
  uint32_t partialCount(uint32_t numRays) const { return gpu::groupsFor(numRays, kRaysPerPartial); }
  // dPred = gradScale * dL/dpred with L = sum (pred - target)^2 / (3 numRays). One dispatch per
  // kPixelBindings bindings of `pixels`. rayLimit (optional): a uint on the device; only the rays
  // below it count (L is their mean, the rest get no dPred and add nothing to the partials).
  void record(gpu::Recorder& rec, uint32_t numRays, const gpu::BufferRange& pred, const gpu::BufferRange& pixelIds,
              std::span<const gpu::BufferRange> pixels, const gpu::BufferRange& cameras,
              const gpu::BufferRange& background, const gpu::BufferRange& dPred, const gpu::BufferRange& partials,
              float gradScale = 1.0f, const gpu::BufferRange* rayLimit = nullptr);
  // The same with every image in one binding.
  void record(gpu::Recorder& rec, uint32_t numRays, const gpu::BufferRange& pred, const gpu::BufferRange& pixelIds,
              const gpu::BufferRange& images, const gpu::BufferRange& cameras, const gpu::BufferRange& background,
              const gpu::BufferRange& dPred, const gpu::BufferRange& partials, float gradScale = 1.0f,
              const gpu::BufferRange* rayLimit = nullptr) {
    record(rec, numRays, pred, pixelIds, std::span<const gpu::BufferRange>(&images, 1), cameras, background, dPred,
           partials, gradScale, rayLimit);
  }

  // Sums partials (in double) into the mean loss of numRays rays.
  static LossStats summarize(std::span<const float> partials, uint32_t numRays);
  // Reads back the partialCount(numRays) partials written by the last submitted record().
  LossStats read(const gpu::Buffer& partials, uint32_t numRays) const;

 private:
  Context& ctx_;
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

#pragma once
// The photometric MSE loss with its gradient (shaders/loss/loss_photometric.comp).
// Layouts: background (BackgroundColors) and predictions are one vec4 per ray, pred = (r, g, b,
// opacity); pixel ids are uvec2(camera, pixel within image) per ray; the training images are packed
// RGBA8 (uint per pixel, R in the low byte) in one or more bindings (nerf::TrainingPixels), image c
// in binding cameras[c].size[3] from its pixel cameras[c].size[2] on (CameraGpu); dPred is one vec4 per ray (opacity component 0); partials is one float per
// workgroup of kRaysPerPartial rays: that workgroup's sum of squared errors over rgb.
#include <cstdint>
#include <optional>
#include <span>

#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"

namespace vknerf::nerf {

struct LossStats {
  double mse = 0;   // mean over rays and the 3 channels
  double psnr = 0;  // -10 log10(mse), 100 dB for a perfect fit
};

// The rays the loss compares with their pixels: `count` rays' predictions, pixel ids and
// backgrounds. rayLimit (optional): a uint on the device; only the rays below it count (the loss is
// their mean, the rest get no dPred and add nothing to the partials).
struct LossRays {
  uint32_t count = 0;
  gpu::BufferRange pred, pixelIds, background;
  std::optional<gpu::BufferRange> rayLimit;
};

// The training images: the pixels' bindings and the cameras that place each image in them.
struct LossTargets {
  std::span<const gpu::BufferRange> pixels;
  gpu::BufferRange cameras;
};

// What the loss writes: dPred = gradScale * dL/dpred, and the partial sums.
struct LossOutputs {
  gpu::BufferRange dPred, partials;
  float gradScale = 1.0f;
};

class PhotometricLoss {
 public:
  static constexpr uint32_t kRaysPerPartial = 128;  // the shader's workgroup size
  static constexpr uint32_t kPixelBindings = 8;     // pixel buffers one dispatch binds

  explicit PhotometricLoss(Context& ctx);
  uint32_t partialCount(uint32_t numRays) const { return gpu::groupsFor(numRays, kRaysPerPartial); }
  // out.dPred = out.gradScale * dL/dpred with L = sum (pred - target)^2 / (3 rays.count). One
  // dispatch per kPixelBindings bindings of targets.pixels.
  void record(gpu::Recorder& rec, const LossRays& rays, const LossTargets& targets, const LossOutputs& out);
  // The same with every image in one binding.
  void record(gpu::Recorder& rec, const LossRays& rays, const gpu::BufferRange& images,
              const gpu::BufferRange& cameras, const LossOutputs& out) {
    record(rec, rays, LossTargets{std::span<const gpu::BufferRange>(&images, 1), cameras}, out);
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

#include "nerf/loss/photometric_loss.h"

#include <algorithm>
#include <string>
#include <vector>

#include "gpu/dispatch/limited_dispatch.h"
#include "core/math/psnr.h"
#include "vknerf/error.h"
#include "loss/loss_photometric_shared.h"

namespace vknerf::nerf {
namespace {
using glsl::LossPush;
constexpr uint32_t kOtherBindings = 7;  // pred, pixel ids, cameras, background, dPred, partials, ray limit

gpu::KernelDesc lossKernel(Context& ctx) {
  const uint32_t needed = kOtherBindings + PhotometricLoss::kPixelBindings;
  if (ctx.properties().limits.maxPerStageDescriptorStorageBuffers < needed)
    throw Error("PhotometricLoss: this device binds " +
                std::to_string(ctx.properties().limits.maxPerStageDescriptorStorageBuffers) +
                " storage buffers per shader stage, the loss needs " + std::to_string(needed));
  return {gpu::shaders::loss_photometric, std::vector<gpu::Binding>(needed, gpu::Binding::Storage), sizeof(LossPush), {}};
}
}  // namespace

PhotometricLoss::PhotometricLoss(Context& ctx)
    : ctx_(ctx),
      kernel_(ctx, lossKernel(ctx)) {}

void PhotometricLoss::record(gpu::Recorder& rec, const LossRays& rays, const LossTargets& targets,
                             const LossOutputs& out) {
  const uint32_t numRays = rays.count;
  const gpu::BufferRange &pred = rays.pred, &pixelIds = rays.pixelIds, &background = rays.background;
  const gpu::BufferRange* rayLimit = rays.rayLimit ? &*rays.rayLimit : nullptr;
  const std::span<const gpu::BufferRange> pixels = targets.pixels;
  const gpu::BufferRange& cameras = targets.cameras;
  const gpu::BufferRange &dPred = out.dPred, &partials = out.partials;
  const float gradScale = out.gradScale;
  if (numRays == 0) return;
  if (rayLimit && gpu::boundBytes(*rayLimit) < 4) throw Error("PhotometricLoss: ray limit binding holds no uint");
  if (pixels.empty()) throw Error("PhotometricLoss: no training pixels bound");
  for (const auto& r : pixels)
    if (gpu::boundBytes(r) > ctx_.properties().limits.maxStorageBufferRange)
      throw Error("PhotometricLoss: a binding of " + std::to_string(gpu::boundBytes(r)) +
                  " bytes of training pixels exceeds this device's maxStorageBufferRange (" +
                  std::to_string(ctx_.properties().limits.maxStorageBufferRange) + ")");
  for (uint32_t first = 0; first < pixels.size(); first += kPixelBindings) {
    std::vector<gpu::BufferRange> b = {pred, pixelIds, cameras, background, dPred, partials};
    // Slots past the last binding repeat one that exists: they are never read.
    for (uint32_t k = 0; k < kPixelBindings; ++k) b.push_back(pixels[std::min<size_t>(first + k, pixels.size() - 1)]);
    b.push_back(rayLimit ? *rayLimit : partials);  // uncut: a placeholder, never read
    LossPush p{numRays, gradScale, first, rayLimit ? 0u : gpu::kNoRowLimit};
    rec.dispatch(kernel_, std::span<const gpu::BufferRange>(b), &p, sizeof p, partialCount(numRays), 1, 1, "loss_photometric");
  }
}

LossStats PhotometricLoss::summarize(std::span<const float> partials, uint32_t numRays) {
  if (numRays == 0) return {0, core::psnrFromMse(0)};
  double sum = 0;
  for (float v : partials) sum += v;
  double mse = sum / (3.0 * numRays);
  return {mse, core::psnrFromMse(mse)};
}

LossStats PhotometricLoss::read(const gpu::Buffer& partials, uint32_t numRays) const {
  uint32_t n = partialCount(numRays);
  std::vector<float> v = n ? partials.download<float>(n) : std::vector<float>{};
  return summarize(v, numRays);
}

}  // namespace vknerf::nerf

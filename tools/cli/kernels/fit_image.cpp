#include "kernels/fit_image.h"

#include <string>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/encoding/frequency_encoding.h"
#include "nerf/loss/background_colors.h"
#include "nerf/loss/photometric_loss.h"
#include "lib/metrics.h"
#include "nerf/network/mlp.h"
#include "nerf/optim/adam.h"
#include "nerf/rays/rays.h"
#include "vknerf/error.h"

namespace vknerf::nerf {

FitImageResult fitImage(Context& ctx, const std::vector<uint32_t>& rgba8, uint32_t width, uint32_t height,
                        const FitImageConfig& config, uint32_t progressEvery,
                        const std::function<void(uint32_t, double)>& progress) {
  const uint64_t pixels = uint64_t(width) * height;
  if (pixels == 0 || rgba8.size() != pixels) throw Error("fit-image: the image is empty or its pixel count is wrong");
  if (pixels > (1u << 24)) throw Error("fit-image: images over 16M pixels are not supported");
  const uint32_t n = uint32_t(pixels);

  // Pixel centres in [-1, 1]^2 (seed §6.7), one vec4 per pixel; the target ignores alpha.
  std::vector<float> uv(size_t(n) * 4, 0.0f), target(size_t(n) * 3);
  std::vector<uint32_t> opaque(rgba8);
  std::vector<uint32_t> ids(size_t(n) * 2, 0);
  for (uint32_t i = 0; i < n; ++i) {
    uv[4 * i] = (float(i % width) + 0.5f) / float(width) * 2.0f - 1.0f;
    uv[4 * i + 1] = (float(i / width) + 0.5f) / float(height) * 2.0f - 1.0f;
    opaque[i] |= 0xff000000u;
    for (int c = 0; c < 3; ++c) target[3 * i + c] = float((rgba8[i] >> (8 * c)) & 0xffu) / 255.0f;
    ids[2 * i + 1] = i;
  }

  FrequencyEncoding enc(ctx, 2, config.encoding ? config.levels : 0, true);
  DenseMlp mlp(ctx, {config.encoding ? enc.outputDims() : 2u, config.width, config.hiddenLayers, 3, config.seed});
  auto uvBuf = gpu::Buffer::of(ctx, uv);
  gpu::Buffer encoded(ctx, uint64_t(n) * mlp.inputStride() * 4);
  const gpu::Buffer& features = config.encoding ? encoded : uvBuf;  // raw (u, v, 0, 0) is already a 4-wide matrix

  auto params = gpu::Buffer::of(ctx, mlp.initialParameters());
  gpu::Buffer grads(ctx, mlp.parameterCount() * 4), m(ctx, mlp.parameterCount() * 4), v(ctx, mlp.parameterCount() * 4);
  grads.zero();
  m.zero();
  v.zero();
  gpu::Buffer out(ctx, uint64_t(n) * 16), dOut(ctx, uint64_t(n) * 16), background(ctx, uint64_t(n) * 16);
  auto images = gpu::Buffer::of(ctx, opaque), pixelIds = gpu::Buffer::of(ctx, ids);
  CameraGpu cam{{0, 0, 0, 0}, {}, {width, height, 0, 0}};
  auto cameras = gpu::Buffer::of(ctx, std::vector<CameraGpu>{cam});
  PhotometricLoss loss(ctx);
  gpu::Buffer partials(ctx, uint64_t(loss.partialCount(n)) * 4);
  Adam adam(ctx, AdamConfig{config.learningRate});
  DenseMlp::Workspace ws(ctx, mlp, n);
  BackgroundColors bg(ctx);

  gpu::Recorder rec(ctx);
  rec.begin();
  bg.recordConstant(rec, background, n, {0, 0, 0});
  if (config.encoding) enc.recordForward(rec, {n, uvBuf, encoded, mlp.inputStride(), 0});
  rec.end();
  rec.submitAndWait();

  for (uint32_t step = 1; step <= config.steps; ++step) {
    rec.begin();
    mlp.recordForward(rec, {n, features, out}, params, &ws);
    loss.record(rec, {n, out, pixelIds, background}, images, cameras, {dOut, partials});
    mlp.recordBackward(rec, {n, features, out}, params, {dOut, grads}, ws);
    adam.record(rec, {uint32_t(mlp.parameterCount()), params, grads, m, v}, step, adam.config().learningRate(step - 1));
    rec.end();
    rec.submitAndWait();
    if (progress && progressEvery && (step % progressEvery == 0 || step == config.steps))
      progress(step, loss.read(partials, n).mse);
  }

  rec.begin();
  mlp.recordForward(rec, {n, features, out}, params, nullptr);
  rec.end();
  rec.submitAndWait();
  auto pred = out.download<float>(size_t(n) * 4);
  FitImageResult r;
  r.rgb.resize(size_t(n) * 3);
  for (uint32_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) r.rgb[3 * i + c] = pred[4 * i + c];
  r.psnr = psnr(r.rgb, target);
  return r;
}

}  // namespace vknerf::nerf

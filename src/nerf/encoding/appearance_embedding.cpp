#include "nerf/encoding/appearance_embedding.h"

#include <algorithm>
#include <string>

#include "encoding/appearance_bias_shared.h"
#include "encoding/appearance_gradient_shared.h"
#include "encoding/appearance_mean_shared.h"
#include "encoding/appearance_weights_gradient_shared.h"
#include "gpu/per_camera_sum_shared.h"
#include "nerf/rays/rays.h"
#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {
constexpr uint32_t kLocal = 64;
static_assert(AppearanceEmbedding::kMaxWidth == 4 * PER_CAMERA_SLOTS, "a photo's sum is at most the scratch's vec4 slots");

uint32_t checkedDims(uint32_t dims) {
  if (dims == 0 || dims % 4 || dims > AppearanceEmbedding::kMaxDims)
    throw Error("appearance embedding: dims must be a multiple of 4 in [4, " +
                std::to_string(AppearanceEmbedding::kMaxDims) + "], got " + std::to_string(dims));
  return dims;
}

uint32_t checkedWidth(uint32_t width) {
  if (width == 0 || width % 4 || width > AppearanceEmbedding::kMaxWidth)
    throw Error("appearance embedding: the colour layer must be a multiple of 4 wide, at most " +
                std::to_string(AppearanceEmbedding::kMaxWidth) + " (model.width at most " +
                std::to_string(2 * AppearanceEmbedding::kMaxWidth) + "), got " + std::to_string(width));
  return width;
}

gpu::KernelDesc kernel(const gpu::ShaderCode& code, size_t bindings, uint32_t pushBytes) {
  return {code, std::vector<gpu::Binding>(bindings, gpu::Binding::Storage), pushBytes, {}};
}

gpu::KernelDesc gradientKernel() {
  gpu::KernelDesc k = kernel(gpu::shaders::appearance_gradient, 7, sizeof(glsl::AppearanceGradientPush));
  k.bindings[2] = gpu::Binding::TexelRgba32f;  // dColour
  return k;
}
}  // namespace

AppearanceEmbedding::AppearanceEmbedding(Context& ctx, uint32_t dims, uint32_t width)
    : dims_(checkedDims(dims)),
      width_(checkedWidth(width)),
      bias_(ctx, kernel(gpu::shaders::appearance_bias, 3, sizeof(glsl::AppearanceBiasPush))),
      gradient_(ctx, gradientKernel()),
      weightsGradient_(ctx, kernel(gpu::shaders::appearance_weights_gradient, 3,
                                   sizeof(glsl::AppearanceWeightsGradientPush))),
      mean_(ctx, kernel(gpu::shaders::appearance_mean, 2, sizeof(glsl::AppearanceMeanPush))),
      maxGroups_(ctx.properties().limits.maxComputeWorkGroupCount[0]) {}

void AppearanceEmbedding::recordBias(gpu::Recorder& rec, const AppearanceParameters& p, uint32_t first, uint32_t count,
                                     const gpu::BufferRange& bias) {
  gpu::requireBytes("AppearanceEmbedding", "vectors", p.vectors, (uint64_t(first) + count) * dims_ * 4);
  gpu::requireBytes("AppearanceEmbedding", "weights", p.weights, uint64_t(dims_) * width_ * 4);
  gpu::requireBytes("AppearanceEmbedding", "bias", bias, uint64_t(count) * width_ * 4);
  if (count == 0) return;
  rec.dispatch(bias_, {p.vectors, p.weights, bias}, glsl::AppearanceBiasPush{count, first, dims_, width_ / 4},
               gpu::groupsFor(count * (width_ / 4), kLocal), 1, 1, "appearance_bias");
}

void AppearanceEmbedding::recordGradient(gpu::Recorder& rec, const AppearanceGradientInputs& in, uint32_t numPhotos,
                                         const AppearanceParameters& p, const AppearanceGradients& g) {
  gpu::requireBytes("AppearanceEmbedding", "pixel ids", in.pixelIds, uint64_t(in.rays) * kPixelIdBytes);
  gpu::requireBytes("AppearanceEmbedding", "row offsets", in.rowOffsets, (uint64_t(in.rays) + 1) * 4);
  gpu::requireBytes("AppearanceEmbedding", "ray count", in.rayCount, 4);
  gpu::requireBytes("AppearanceEmbedding", "vectors", p.vectors, uint64_t(numPhotos) * dims_ * 4);
  gpu::requireBytes("AppearanceEmbedding", "weights", p.weights, uint64_t(dims_) * width_ * 4);
  gpu::requireBytes("AppearanceEmbedding", "vector gradients", g.vectors, uint64_t(numPhotos) * dims_ * 4);
  gpu::requireBytes("AppearanceEmbedding", "weight gradients", g.weights, uint64_t(dims_) * width_ * 4);
  gpu::requireBytes("AppearanceEmbedding", "photo sums", g.photoSums, uint64_t(numPhotos) * width_ * 4);
  if (numPhotos == 0) return;
  // gpu/per_camera_sum.glsl: a workgroup a photo at a time, as many as one dispatch holds.
  rec.dispatch(gradient_, {in.pixelIds, in.rowOffsets, in.dColour, p.weights, g.photoSums, g.vectors, in.rayCount},
               glsl::AppearanceGradientPush{numPhotos, in.rays, width_ / 4, dims_}, std::min(numPhotos, maxGroups_), 1,
               1, "appearance_gradient");
  rec.dispatch(weightsGradient_, {p.vectors, g.photoSums, g.weights},
               glsl::AppearanceWeightsGradientPush{numPhotos, dims_, width_ / 4},
               gpu::groupsFor(dims_ * (width_ / 4), kLocal), 1, 1, "appearance_weights_gradient");
}

void AppearanceEmbedding::recordMean(gpu::Recorder& rec, uint32_t numPhotos, const gpu::BufferRange& table,
                                     const gpu::BufferRange& mean) {
  gpu::requireBytes("AppearanceEmbedding", "table", table, uint64_t(std::max(numPhotos, 1u)) * dims_ * 4);
  gpu::requireBytes("AppearanceEmbedding", "mean", mean, uint64_t(dims_) * 4);
  rec.dispatch(mean_, {table, mean}, glsl::AppearanceMeanPush{numPhotos, dims_ / 4}, 1, 1, 1, "appearance_mean");
}

}  // namespace vknerf::nerf

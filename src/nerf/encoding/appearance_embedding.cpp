#include "nerf/encoding/appearance_embedding.h"

#include <algorithm>
#include <string>

#include "encoding/appearance_gradient_shared.h"
#include "encoding/appearance_mean_shared.h"
#include "encoding/appearance_rows_shared.h"
#include "gpu/per_camera_sum_shared.h"
#include "nerf/rays/rays.h"
#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {
constexpr uint32_t kLocal = 64;
static_assert(AppearanceEmbedding::kMaxDims == 4 * PER_CAMERA_SLOTS, "a photo's sum is at most the scratch's vec4 slots");

uint32_t checkedDims(uint32_t dims) {
  if (dims == 0 || dims % 4 || dims > AppearanceEmbedding::kMaxDims)
    throw Error("appearance embedding: dims must be a multiple of 4 in [4, " +
                std::to_string(AppearanceEmbedding::kMaxDims) + "], got " + std::to_string(dims));
  return dims;
}
}  // namespace

AppearanceEmbedding::AppearanceEmbedding(Context& ctx, uint32_t dims)
    : ctx_(ctx),
      dims_(checkedDims(dims)),
      rows_(ctx, {gpu::shaders::appearance_rows, std::vector<gpu::Binding>(5, gpu::Binding::Storage),
                  sizeof(glsl::AppearanceRowsPush), {}}),
      gradient_(ctx, {gpu::shaders::appearance_gradient, std::vector<gpu::Binding>(5, gpu::Binding::Storage),
                      sizeof(glsl::AppearanceGradientPush), {}}),
      mean_(ctx, {gpu::shaders::appearance_mean, std::vector<gpu::Binding>(2, gpu::Binding::Storage),
                  sizeof(glsl::AppearanceMeanPush), {}}),
      limited_(ctx),
      maxGroups_(ctx.properties().limits.maxComputeWorkGroupCount[0]) {}

void AppearanceEmbedding::recordRows(gpu::Recorder& rec, const AppearanceRows& rows, const gpu::BufferRange& table) {
  if (rows.stride % 4 || rows.columnOffset % 4 || rows.columnOffset + dims_ > rows.stride)
    throw Error("AppearanceEmbedding: columns [" + std::to_string(rows.columnOffset) + ", " +
                std::to_string(rows.columnOffset + dims_) + ") do not fit 4-aligned rows of " + std::to_string(rows.stride));
  if (rows.pixelIds.has_value() != rows.sampleRay.has_value())
    throw Error("AppearanceEmbedding: pixel ids and sample rays go together");
  const bool perRay = rows.pixelIds.has_value();
  gpu::requireBytes("AppearanceEmbedding", "features", rows.features, uint64_t(rows.count) * rows.stride * 4);
  gpu::requireBytes("AppearanceEmbedding", "table", table, uint64_t(perRay ? 1 : rows.fixedRow + 1) * dims_ * 4);
  if (perRay) gpu::requireBytes("AppearanceEmbedding", "sample rays", *rows.sampleRay, uint64_t(rows.count) * 4);
  if (rows.count == 0) return;
  const gpu::BufferRange* limit = rows.rowLimit ? &*rows.rowLimit : nullptr;
  limited_.begin(rec, limit, rows.count, rows.count, {kLocal});
  glsl::AppearanceRowsPush p{rows.count, rows.stride / 4, rows.columnOffset / 4, dims_ / 4,
                             perRay ? APPEARANCE_PER_RAY : rows.fixedRow, 0};
  // Unused bindings in a render: the table stands in (never read).
  gpu::dispatchLimited(rec, rows_, {table, perRay ? *rows.pixelIds : table, perRay ? *rows.sampleRay : table, rows.features},
                       p, limited_.rows(0, 0), gpu::groupsFor(rows.count, kLocal), "appearance_rows");
}

void AppearanceEmbedding::recordGradient(gpu::Recorder& rec, const AppearanceGradientInputs& in, uint32_t numPhotos,
                                         const gpu::BufferRange& grads) {
  if (in.stride % 4 || in.columnOffset % 4 || in.columnOffset + dims_ > in.stride)
    throw Error("AppearanceEmbedding: gradient columns do not fit 4-aligned rows of " + std::to_string(in.stride));
  gpu::requireBytes("AppearanceEmbedding", "pixel ids", in.pixelIds, uint64_t(in.rays) * kPixelIdBytes);
  gpu::requireBytes("AppearanceEmbedding", "row offsets", in.rowOffsets, (uint64_t(in.rays) + 1) * 4);
  gpu::requireBytes("AppearanceEmbedding", "ray count", in.rayCount, 4);
  gpu::requireBytes("AppearanceEmbedding", "gradients", grads, uint64_t(numPhotos) * dims_ * 4);
  if (numPhotos == 0) return;
  glsl::AppearanceGradientPush p{numPhotos, in.rays, in.stride / 4, in.columnOffset / 4, dims_ / 4};
  // gpu/per_camera_sum.glsl: a workgroup a photo at a time, as many as one dispatch holds.
  rec.dispatch(gradient_, {in.pixelIds, in.rowOffsets, in.dDir, grads, in.rayCount}, p, std::min(numPhotos, maxGroups_), 1,
               1, "appearance_gradient");
}

void AppearanceEmbedding::recordMean(gpu::Recorder& rec, uint32_t numPhotos, const gpu::BufferRange& table,
                                     const gpu::BufferRange& mean) {
  gpu::requireBytes("AppearanceEmbedding", "table", table, uint64_t(std::max(numPhotos, 1u)) * dims_ * 4);
  gpu::requireBytes("AppearanceEmbedding", "mean", mean, uint64_t(dims_) * 4);
  rec.dispatch(mean_, {table, mean}, glsl::AppearanceMeanPush{numPhotos, dims_ / 4}, 1, 1, 1, "appearance_mean");
}

}  // namespace vknerf::nerf

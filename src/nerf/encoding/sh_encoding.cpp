#include "nerf/encoding/sh_encoding.h"

#include <algorithm>
#include <string>

#include "vknerf/error.h"
#include "encoding/encode_sh_shared.h"

namespace vknerf::nerf {
namespace {
using Push = glsl::ShPush;
constexpr uint32_t kLocal = 64;

uint32_t checkedDegree(uint32_t degree) {
  if (degree < 1 || degree > 4) throw Error("ShEncoding: degree must be 1..4, got " + std::to_string(degree));
  return degree;
}

}  // namespace

ShEncoding::ShEncoding(Context& ctx, uint32_t degree)
    : ctx_(ctx),
      degree_(checkedDegree(degree)),
      kernel_(ctx, {gpu::shaders::encode_sh, {gpu::Binding::TexelRgba32f, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                    sizeof(Push),
                    {{glsl::ShSpec::DEGREE, degree}}}),
      limited_(ctx) {}

void ShEncoding::recordForward(gpu::Recorder& rec, const EncodedRows& rows, const gpu::BufferRange&) {
  const uint32_t count = rows.count, stride = rows.stride, columnOffset = rows.columnOffset;
  const gpu::BufferRange &directions = rows.inputs, &features = rows.features;
  const gpu::BufferRange* rowLimit = rows.rowLimit ? &*rows.rowLimit : nullptr;
  if (stride % 4 || columnOffset % 4)
    throw Error("ShEncoding: stride " + std::to_string(stride) + " and column offset " + std::to_string(columnOffset) +
                " must be multiples of 4");
  if (columnOffset + paddedDims() > stride)
    throw Error("ShEncoding: columns [" + std::to_string(columnOffset) + ", " +
                std::to_string(columnOffset + paddedDims()) + ") do not fit a row of " + std::to_string(stride));
  if (count == 0) return;
  if (rowLimit && gpu::boundBytes(*rowLimit) < 4) throw Error("ShEncoding: row limit binding holds no uint");
  const VkDeviceSize rowBytes = VkDeviceSize(stride) * 4;
  if (gpu::boundBytes(features) < count * rowBytes || gpu::boundBytes(directions) < VkDeviceSize(count) * 16)
    throw Error("ShEncoding: buffers too small for " + std::to_string(count) + " rows");
  // Matrices beyond one binding are encoded in chunks of rows bound at their own offsets (the
  // directions are read as one texel per row).
  const uint32_t chunk = std::min(count, gpu::rowsPerBinding(ctx_, rowBytes, 1));
  const gpu::BufferRange* gather = rows.rowGather ? &*rows.rowGather : nullptr;
  if (gather) gpu::requireGatherInOneChunk("ShEncoding", *gather, count, chunk);
  limited_.begin(rec, rowLimit, count, chunk, {kLocal});
  gpu::forRowChunks(count, chunk, [&](uint32_t first, uint32_t n, uint32_t c) {
    const gpu::BufferRange out = gpu::rowsOf(features, rowBytes, first, n);
    gpu::dispatchLimited(rec, kernel_, {gpu::rowsOf(directions, 16, first, n), out, gather ? *gather : out},
                         Push{n, stride / 4, columnOffset / 4, 0, gather ? 1u : 0u}, limited_.rows(c, 0),
                         gpu::groupsFor(n, kLocal), "encode_sh");
  });
}

}  // namespace vknerf::nerf

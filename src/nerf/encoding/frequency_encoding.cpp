#include "nerf/encoding/frequency_encoding.h"

#include <algorithm>
#include <string>

#include "core/layouts/frequency_layout.h"
#include "vknerf/error.h"
#include "encoding/encode_frequency_shared.h"

namespace vknerf::nerf {
namespace {
using Push = glsl::FrequencyPush;
constexpr uint32_t kLocal = 64;

uint32_t checkedDims(uint32_t inputDims, uint32_t levels) {
  if (inputDims < 1 || inputDims > 4)
    throw Error("FrequencyEncoding: input dims must be 1..4, got " + std::to_string(inputDims));
  // 2^15 p stays far below 2^24, where the exact period reduction would run out of bits.
  if (levels > 16) throw Error("FrequencyEncoding: at most 16 levels, got " + std::to_string(levels));
  return inputDims;
}

}  // namespace

FrequencyEncoding::FrequencyEncoding(Context& ctx, uint32_t inputDims, uint32_t levels, bool includeInput)
    : ctx_(ctx),
      inputDims_(checkedDims(inputDims, levels)),
      levels_(levels),
      outputDims_(core::frequencyEncodingDims(inputDims, levels, includeInput)),
      includeInput_(includeInput),
      kernel_(ctx, {gpu::shaders::encode_frequency, {gpu::Binding::Storage, gpu::Binding::Storage}, sizeof(Push),
                    {{glsl::FrequencySpec::DIMS, inputDims},
                     {glsl::FrequencySpec::LEVELS, levels},
                     {glsl::FrequencySpec::INCLUDE_INPUT, includeInput ? 1u : 0u}}}) {
  if (outputDims_ == 0) throw Error("FrequencyEncoding: no output columns (0 levels and no raw input)");
}

void FrequencyEncoding::recordForward(gpu::Recorder& rec, const EncodedRows& rows, const gpu::BufferRange&) {
  const uint32_t count = rows.count, stride = rows.stride, columnOffset = rows.columnOffset;
  const gpu::BufferRange &inputs = rows.inputs, &features = rows.features;
  if (rows.rowLimit || rows.rowGather) throw Error("FrequencyEncoding: no row limit or gather (every row is encoded)");
  if (stride % 4 || columnOffset % 4)
    throw Error("FrequencyEncoding: stride " + std::to_string(stride) + " and column offset " +
                std::to_string(columnOffset) + " must be multiples of 4");
  if (columnOffset + paddedDims() > stride)
    throw Error("FrequencyEncoding: columns [" + std::to_string(columnOffset) + ", " +
                std::to_string(columnOffset + paddedDims()) + ") do not fit a row of " + std::to_string(stride));
  if (count == 0) return;
  const VkDeviceSize need = VkDeviceSize(count) * stride * 4;
  if (gpu::boundBytes(features) < need || gpu::boundBytes(inputs) < VkDeviceSize(count) * 16)
    throw Error("FrequencyEncoding: buffers too small for " + std::to_string(count) + " rows");
  // A matrix larger than one descriptor can bind (128 MiB on lavapipe) is encoded in chunks of
  // rows, each bound at its own offset.
  const VkDeviceSize rowBytes = VkDeviceSize(stride) * 4;
  const uint32_t chunk = std::min(count, gpu::rowsPerBinding(ctx_, rowBytes));
  gpu::forRowChunks(count, chunk, [&](uint32_t first, uint32_t n, uint32_t) {
    Push p{n, stride / 4, columnOffset / 4};
    rec.dispatch(kernel_, {gpu::rowsOf(inputs, 16, first, n), gpu::rowsOf(features, rowBytes, first, n)}, p,
                 gpu::groupsFor(n, kLocal), 1, 1, "encode_frequency");
  });
}

}  // namespace vknerf::nerf

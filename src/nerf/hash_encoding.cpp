#include "nerf/hash_encoding.h"

#include <algorithm>
#include <string>

#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {
constexpr uint32_t kLocal = 64;

const HashGridConfig& checked(const HashGridConfig& c, Context& ctx) {
  auto fail = [](const std::string& m) { throw Error("HashEncoding: " + m); };
  if (c.levels < 1 || c.levels > 24) fail("levels must be 1..24, got " + std::to_string(c.levels));
  const uint32_t F = c.featuresPerLevel;
  if (F != 1 && F != 2 && F != 4 && F != 8) fail("features per level must be 1, 2, 4 or 8, got " + std::to_string(F));
  // T >= 2: a level's slot is a whole number of texels (the forward pass reads the table as rgba32f).
  if (c.log2TableSize < 2 || c.log2TableSize > 24) fail("log2 table size must be 2..24, got " + std::to_string(c.log2TableSize));
  if (c.baseResolution < 1) fail("base resolution must be at least 1");
  if (!(c.growthFactor >= 1.0)) fail("growth factor must be >= 1, got " + std::to_string(c.growthFactor));
  // Vertex coordinates reach res; the hash and the dense index are uint32 arithmetic.
  if (ref::hashGridResolution(c, c.levels - 1) > (1u << 24))
    fail("finest resolution " + std::to_string(ref::hashGridResolution(c, c.levels - 1)) + " exceeds 2^24");
  const VkDeviceSize bytes = VkDeviceSize(ref::hashGridParameterCount(c)) * 4;
  if (bytes > ctx.properties().limits.maxStorageBufferRange)
    fail("table of " + std::to_string(bytes) + " bytes exceeds one storage binding (" +
         std::to_string(ctx.properties().limits.maxStorageBufferRange) + "); lower levels, F or T");
  return c;
}
}  // namespace

HashEncoding::HashEncoding(Context& ctx, HashGridConfig config, HashBackwardMode mode)
    : ctx_(ctx),
      config_(checked(config, ctx)),
      mode_(mode),
      forward_(ctx, {"encode_hash",
                     {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f, gpu::Binding::Storage,
                      gpu::Binding::Storage},
                     sizeof(Push), {config.levels, config.featuresPerLevel, config.log2TableSize}}),
      noLimit_(ctx, 16),
      limited_(ctx) {
  for (uint32_t l = 0; l < config_.levels; ++l) {
    push_.res[l] = resolution(l);
    if (dense(l)) push_.denseMask |= 1u << l;
  }
  // Without float atomics the forward pass still works (inference); recordBackward says why not.
  if (ctx.floatAtomics())
    backward_ = gpu::Kernel(ctx, {"encode_hash_backward",
                                  {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f, gpu::Binding::Storage},
                                  sizeof(Push),
                                  {config.levels, config.featuresPerLevel, config.log2TableSize, uint32_t(mode)}});
}

std::vector<float> HashEncoding::initialParameters(uint32_t seed) const {
  return ref::hashGridInitialParameters(config_, seed);
}

// The table's own range, so parameters inside a larger buffer bind no more than one binding allows.
gpu::BufferRange HashEncoding::exactly(const gpu::BufferRange& table) const {
  return gpu::BufferRange(*table.buffer, table.offset, VkDeviceSize(parameterCount()) * 4);
}

template <class Fn>
void HashEncoding::forChunks(uint32_t count, uint32_t stride, uint32_t columnOffset, const gpu::BufferRange& positions,
                             const gpu::BufferRange& matrix, const gpu::BufferRange& table, const char* what, Fn&& fn) {
  const std::string name = std::string("HashEncoding::") + what + ": ";
  if (stride % 4 || columnOffset % 4)
    throw Error(name + "stride " + std::to_string(stride) + " and column offset " + std::to_string(columnOffset) +
                " must be multiples of 4");
  if (columnOffset + paddedDims() > stride)
    throw Error(name + "columns [" + std::to_string(columnOffset) + ", " + std::to_string(columnOffset + paddedDims()) +
                ") do not fit a row of " + std::to_string(stride));
  if (gpu::boundBytes(table) < VkDeviceSize(parameterCount()) * 4)
    throw Error(name + "parameter buffer holds fewer than " + std::to_string(parameterCount()) + " floats");
  if (count == 0) return;
  const VkDeviceSize rowBytes = VkDeviceSize(stride) * 4;
  if (gpu::boundBytes(matrix) < count * rowBytes || gpu::boundBytes(positions) < VkDeviceSize(count) * 16)
    throw Error(name + "buffers too small for " + std::to_string(count) + " rows");
  // Rows beyond one binding (storage range or texel count) go in chunks bound at row offsets.
  const uint32_t chunk = std::min(count, gpu::rowsPerBinding(ctx_, rowBytes, std::max<uint64_t>(stride / 4, 1)));
  for (uint32_t first = 0; first < count; first += chunk) {
    const uint32_t n = std::min(chunk, count - first);
    gpu::BufferRange in(*positions.buffer, positions.offset + VkDeviceSize(first) * 16, VkDeviceSize(n) * 16);
    gpu::BufferRange m(*matrix.buffer, matrix.offset + first * rowBytes, n * rowBytes);
    Push p = push_;
    p.count = n, p.strideVec4 = stride / 4, p.offsetVec4 = columnOffset / 4, p.limitBase = gpu::kNoRowLimit;
    fn(in, m, p, gpu::groupsFor(n, kLocal), first / chunk, chunk);
  }
}

void HashEncoding::recordForward(gpu::Recorder& rec, const gpu::BufferRange& positions, uint32_t count,
                                 const gpu::BufferRange& params, const gpu::BufferRange& features, uint32_t stride,
                                 uint32_t columnOffset, const gpu::BufferRange* rowLimit) {
  if (rowLimit && gpu::boundBytes(*rowLimit) < 4) throw Error("HashEncoding::recordForward: row limit binding holds no uint");
  if (params.offset % ctx_.properties().limits.minTexelBufferOffsetAlignment)
    throw Error("HashEncoding::recordForward: parameter offset " + std::to_string(params.offset) +
                " is not a multiple of minTexelBufferOffsetAlignment");
  forChunks(count, stride, columnOffset, positions, features, params, "recordForward",
            [&](const gpu::BufferRange& in, const gpu::BufferRange& out, Push p, uint32_t groups, uint32_t c,
                uint32_t chunkRows) {
              if (!rowLimit) {
                rec.dispatch(forward_, {in, exactly(params), out, noLimit_}, p, groups, 1, 1, "encode_hash");
                return;
              }
              if (c == 0) limited_.recordArgs(rec, *rowLimit, count, chunkRows, {kLocal});
              const gpu::LimitedRows l = limited_.rows(c, 0);
              p.limitBase = l.base;
              rec.dispatchIndirect(forward_, {in, exactly(params), out, l.limit}, &p, sizeof p, *l.args, l.argsOffset,
                                   "encode_hash");
            });
}

void HashEncoding::recordBackward(gpu::Recorder& rec, const gpu::BufferRange& positions, uint32_t count,
                                  const gpu::BufferRange& dFeatures, uint32_t stride, uint32_t columnOffset,
                                  const gpu::BufferRange& grads) {
  if (!ctx_.floatAtomics())
    throw Error("HashEncoding::recordBackward: the device lacks float atomics (VK_EXT_shader_atomic_float "
                "shaderBufferFloat32AtomicAdd), which the table gradient scatter needs");
  forChunks(count, stride, columnOffset, positions, dFeatures, grads, "recordBackward",
            [&](const gpu::BufferRange& in, const gpu::BufferRange& dF, const Push& p, uint32_t groups, uint32_t,
                uint32_t) {
              rec.dispatch(backward_, {in, dF, exactly(grads)}, p, groups, 1, 1, "encode_hash_backward");
            });
}

}  // namespace vknerf::nerf

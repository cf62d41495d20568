#include "nerf/encoding/hash_encoding.h"

#include <algorithm>
#include <string>

#include "encoding/encode_hash_backward_reduce_shared.h"
#include "encoding/hash_grid_shared.h"
#include "gpu/dispatch/prefix_sum.h"
#include "nerf/network/gradient_paths.h"
#include "vknerf/error.h"

namespace vknerf::nerf {
namespace {
constexpr uint32_t kLocal = 64;
// SortReduce: slots per reduce invocation (encode_hash_backward_reduce.comp's CHUNK). Its loops run
// at most 3 * kChunk times per invocation, far below lavapipe's 65,535-iteration loop limiter even
// if the limit counted a whole 64-wide workgroup; larger chunks mean fewer entries spanning chunks.
constexpr uint32_t kChunk = 256;
constexpr VkDeviceSize kSortSlotBytes = VkDeviceSize(128) << 20;  // default budget of sorted slots
// Bytes of one sorted slot: (F + 4) / 4 uvec4s, the entry and the F values (encode_hash_backward_scatter.comp).
uint32_t slotBytes(uint32_t F) { return (F + 4) / 4 * 16; }

// Outputs the PrefixSum can scan in one dispatch per level (its scan_add covers one x-dispatch).
uint64_t scanCapacity(Context& ctx) { return uint64_t(ctx.properties().limits.maxComputeWorkGroupCount[0]) * 256; }

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
  if (core::hashGridResolution(c, c.levels - 1) > (1u << 24))
    fail("finest resolution " + std::to_string(core::hashGridResolution(c, c.levels - 1)) + " exceeds 2^24");
  const VkDeviceSize bytes = VkDeviceSize(core::hashGridParameterCount(c)) * 4;
  if (bytes > ctx.properties().limits.maxStorageBufferRange)
    fail("table of " + std::to_string(bytes) + " bytes exceeds one storage binding (" +
         std::to_string(ctx.properties().limits.maxStorageBufferRange) + "); lower levels, F or T");
  return c;
}

// The grid's shape, which the forward pass and every backward kernel but the reduce specialize on.
std::vector<gpu::SpecConstant> gridSpec(const HashGridConfig& c) {
  using Spec = glsl::HashGridSpec;
  return {{Spec::LEVELS, c.levels}, {Spec::FEATURES, c.featuresPerLevel}, {Spec::LOG2_TABLE, c.log2TableSize},
          {Spec::CONTRACT, c.contraction}};
}

// The scatter's module (encoding/encode_hash_backward.glsl): with the position gradient or not,
// a subgroup's adds merged (SubgroupMerged), compare-and-swap loops (CompareSwap) or float atomics.
const gpu::ShaderCode& backwardShader(HashBackwardMode mode, bool position) {
  if (mode == HashBackwardMode::SubgroupMerged)
    return position ? gpu::shaders::encode_hash_backward_position_merged : gpu::shaders::encode_hash_backward_merged;
  if (mode == HashBackwardMode::CompareSwap)
    return position ? gpu::shaders::encode_hash_backward_position_cas : gpu::shaders::encode_hash_backward_cas;
  return position ? gpu::shaders::encode_hash_backward_position : gpu::shaders::encode_hash_backward;
}
}  // namespace

HashEncoding::HashEncoding(Context& ctx, HashGridConfig config) : HashEncoding(ctx, config, gradientPathsFor(ctx).hash) {}

HashEncoding::HashEncoding(Context& ctx, HashGridConfig config, HashBackwardMode mode)
    : ctx_(ctx),
      config_(checked(config, ctx)),
      mode_(mode),
      forward_(ctx, {gpu::shaders::encode_hash,
                     {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f, gpu::Binding::Storage,
                      gpu::Binding::Storage, gpu::Binding::Storage},
                     sizeof(Push), gridSpec(config)}),
      limited_(ctx),
      limitedBackward_(ctx),
      limitedPosition_(ctx) {
  for (uint32_t l = 0; l < config_.levels; ++l) {
    push_.res[l] = resolution(l);
    if (dense(l)) push_.denseMask |= 1u << l;
  }
  if (mode_ == HashBackwardMode::SubgroupMerged && !gradientPathsFor(ctx).hashSubgroupMerge)
    throw Error("HashEncoding: SubgroupMerged needs subgroup vote and arithmetic in compute shaders; use Atomic");
  if (mode_ == HashBackwardMode::SortReduce) {
    // Entries of one level are the unit of a pass: the prefix sum must hold 2^T of them.
    if ((uint64_t(1) << config_.log2TableSize) > scanCapacity(ctx))
      throw Error("HashEncoding: SortReduce scans 2^" + std::to_string(config_.log2TableSize) +
                  " entries per level, more than one prefix-sum dispatch covers (" +
                  std::to_string(scanCapacity(ctx)) + "); lower T or use Atomic");
    const std::vector<gpu::SpecConstant> spec = gridSpec(config);
    count_ = gpu::Kernel(ctx, {gpu::shaders::encode_hash_backward_count,
                               {gpu::Binding::TexelRgba32f, gpu::Binding::Storage, gpu::Binding::Storage},
                               sizeof(SortPush), spec});
    scatter_ = gpu::Kernel(ctx, {gpu::shaders::encode_hash_backward_scatter,
                                 {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f, gpu::Binding::Storage,
                                  gpu::Binding::Storage, gpu::Binding::Storage},
                                 sizeof(SortPush), spec});
    for (uint32_t stage = 0; stage < 3; ++stage)
      reduce_[stage] = gpu::Kernel(ctx, {gpu::shaders::encode_hash_backward_reduce,
                                         std::vector<gpu::Binding>(5, gpu::Binding::Storage),
                                         sizeof(glsl::HashReducePush),
                                         {{glsl::HashReduceSpec::FEATURES, config.featuresPerLevel},
                                          {glsl::HashReduceSpec::CHUNK, kChunk},
                                          {glsl::HashReduceSpec::STAGE, stage}}});
    setSortSlotBudget(uint32_t(std::min<VkDeviceSize>(
        kSortSlotBytes, ctx.properties().limits.maxStorageBufferRange) / slotBytes(config.featuresPerLevel)));
  } else if (ctx.floatAtomics() || mode_ == HashBackwardMode::CompareSwap) {
    // Without float atomics the forward pass still works (inference); recordBackward says why not.
    backward_ = gpu::Kernel(ctx, {backwardShader(mode, false),
                                  {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f, gpu::Binding::Storage,
                                   gpu::Binding::Storage},
                                  sizeof(Push), gridSpec(config)});
  }
}

HashEncoding::~HashEncoding() = default;

void HashEncoding::setSortSlotBudget(uint32_t slots) {
  const uint64_t most = ctx_.properties().limits.maxStorageBufferRange / slotBytes(config_.featuresPerLevel);
  if (slots < 8 || slots > most)
    throw Error("HashEncoding::setSortSlotBudget: " + std::to_string(slots) + " slots; must be 8.." +
                std::to_string(most) + " (one sample's 8 corners, and the values within one binding)");
  slotBudget_ = slots;
}

std::vector<float> HashEncoding::initialParameters(uint32_t seed) const {
  return core::hashGridInitialParameters(config_, seed);
}

std::vector<ParameterRange> HashEncoding::trainedParts() const {
  std::vector<ParameterRange> parts;
  for (const core::TableRun& r : core::hashGridUsedRuns(config_)) parts.push_back({uint32_t(r.first), uint32_t(r.count)});
  return parts;
}

void HashEncoding::recordBackward(gpu::Recorder& rec, const EncodedRows& rows, const EncodingGradients& gradients) {
  std::optional<PositionGradientTarget> position;
  if (gradients.dInputs) position = PositionGradientTarget{gradients.params, *gradients.dInputs};
  recordBackward(rec, rows, gradients.grads, position);
}

// The table's own range, so parameters inside a larger buffer bind no more than one binding allows.
gpu::BufferRange HashEncoding::exactly(const gpu::BufferRange& table) const {
  return gpu::BufferRange(*table.buffer, table.offset, VkDeviceSize(parameterCount()) * 4);
}

template <class Fn>
void HashEncoding::forChunks(const EncodedRows& rows, const gpu::BufferRange& table, const char* what, Fn&& fn) {
  const uint32_t count = rows.count, stride = rows.stride, columnOffset = rows.columnOffset;
  const gpu::BufferRange &positions = rows.inputs, &matrix = rows.features;
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
  gpu::forRowChunks(count, chunk, [&](uint32_t first, uint32_t n, uint32_t c) {
    Push p = push_;
    p.count = n, p.strideVec4 = stride / 4, p.offsetVec4 = columnOffset / 4, p.limitBase = gpu::kNoRowLimit;
    fn(gpu::rowsOf(positions, 16, first, n), gpu::rowsOf(matrix, rowBytes, first, n), p, gpu::groupsFor(n, kLocal), c,
       chunk);
  });
}

void HashEncoding::recordForward(gpu::Recorder& rec, const EncodedRows& rows, const gpu::BufferRange& params) {
  const gpu::BufferRange* rowLimit = rows.rowLimit ? &*rows.rowLimit : nullptr;
  if (rowLimit && gpu::boundBytes(*rowLimit) < 4) throw Error("HashEncoding::recordForward: row limit binding holds no uint");
  if (params.offset % ctx_.properties().limits.minTexelBufferOffsetAlignment)
    throw Error("HashEncoding::recordForward: parameter offset " + std::to_string(params.offset) +
                " is not a multiple of minTexelBufferOffsetAlignment");
  const gpu::BufferRange* gather = rows.rowGather ? &*rows.rowGather : nullptr;
  forChunks(rows, params, "recordForward",
            [&](const gpu::BufferRange& in, const gpu::BufferRange& out, Push p, uint32_t groups, uint32_t c,
                uint32_t chunkRows) {
              if (c == 0) {
                if (gather) gpu::requireGatherInOneChunk("HashEncoding::recordForward", *gather, rows.count, chunkRows);
                limited_.begin(rec, rowLimit, rows.count, chunkRows, {kLocal});
              }
              p.gather = gather ? 1u : 0u;
              gpu::dispatchLimited(rec, forward_, {in, exactly(params), out, gather ? *gather : out}, p,
                                   limited_.rows(c, 0), groups, "encode_hash");
            });
}

void HashEncoding::recordBackward(gpu::Recorder& rec, const EncodedRows& rows, const gpu::BufferRange& grads,
                                  const std::optional<PositionGradientTarget>& position) {
  const gpu::BufferRange* rowLimit = rows.rowLimit ? &*rows.rowLimit : nullptr;
  if (rowLimit && gpu::boundBytes(*rowLimit) < 4) throw Error("HashEncoding::recordBackward: row limit binding holds no uint");
  if (mode_ == HashBackwardMode::SortReduce) {
    // The sort passes are dispatched for the whole chunk; their kernels skip the rows past the limit.
    forChunks(rows, grads, "recordBackward",
              [&](const gpu::BufferRange& in, const gpu::BufferRange& dF, const Push& p, uint32_t, uint32_t c,
                  uint32_t chunkRows) {
                const gpu::LimitedRows L = rowLimit ? gpu::LimitedRows{*rowLimit, c * chunkRows} : limited_.uncut();
                recordSortReduce(rec, in, dF, p, grads, L);
              });
    if (position) recordPositionGradient(rec, rows, position->params, position->dPositions);
    return;
  }
  if (!ctx_.floatAtomics() && mode_ != HashBackwardMode::CompareSwap)
    throw Error("HashEncoding::recordBackward: the device lacks float atomics (VK_EXT_shader_atomic_float "
                "shaderBufferFloat32AtomicAdd), which the table gradient scatter needs (HashBackwardMode::SortReduce "
                "and CompareSwap do not)");
  if (position) {
    checkPositionGradient(rows, position->params, position->dPositions, "recordBackward");
    if (!backwardWithPosition_)
      backwardWithPosition_.emplace(ctx_, gpu::KernelDesc{backwardShader(mode_, true),
                                                          {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f,
                                                           gpu::Binding::Storage, gpu::Binding::TexelRgba32f,
                                                           gpu::Binding::Storage, gpu::Binding::Storage},
                                                          sizeof(Push), gridSpec(config_)});
  }
  forChunks(rows, grads, "recordBackward",
            [&](const gpu::BufferRange& in, const gpu::BufferRange& dF, Push p, uint32_t groups, uint32_t c,
                uint32_t chunkRows) {
              if (c == 0) limitedBackward_.begin(rec, rowLimit, rows.count, chunkRows, {kLocal});
              if (!position) {
                gpu::dispatchLimited(rec, backward_, {in, dF, exactly(grads)}, p, limitedBackward_.rows(c, 0), groups,
                                     "encode_hash_backward");
                return;
              }
              const gpu::BufferRange out = gpu::rowsOf(position->dPositions, 16, c * chunkRows, p.count);
              gpu::dispatchLimited(rec, *backwardWithPosition_, {in, dF, exactly(grads), exactly(position->params), out},
                                   p, limitedBackward_.rows(c, 0), groups, "encode_hash_backward_position");
            });
}

void HashEncoding::checkPositionGradient(const EncodedRows& rows, const gpu::BufferRange& params,
                                         const gpu::BufferRange& dPositions, const char* what) const {
  const std::string name = std::string("HashEncoding::") + what + ": ";
  if (params.offset % ctx_.properties().limits.minTexelBufferOffsetAlignment)
    throw Error(name + "parameter offset " + std::to_string(params.offset) +
                " is not a multiple of minTexelBufferOffsetAlignment");
  if (gpu::boundBytes(params) < VkDeviceSize(parameterCount()) * 4)
    throw Error(name + "parameter buffer holds fewer than " + std::to_string(parameterCount()) + " floats");
  if (gpu::boundBytes(dPositions) < VkDeviceSize(rows.count) * 16)
    throw Error(name + "the position gradient holds fewer than " + std::to_string(rows.count) + " vec4s");
}

void HashEncoding::recordPositionGradient(gpu::Recorder& rec, const EncodedRows& rows, const gpu::BufferRange& params,
                                          const gpu::BufferRange& dPositions) {
  const gpu::BufferRange* rowLimit = rows.rowLimit ? &*rows.rowLimit : nullptr;
  if (rowLimit && gpu::boundBytes(*rowLimit) < 4)
    throw Error("HashEncoding::recordPositionGradient: row limit binding holds no uint");
  checkPositionGradient(rows, params, dPositions, "recordPositionGradient");
  if (!positionGradient_)
    positionGradient_.emplace(ctx_, gpu::KernelDesc{gpu::shaders::encode_hash_position_gradient,
                                                    {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f,
                                                     gpu::Binding::TexelRgba32f, gpu::Binding::Storage,
                                                     gpu::Binding::Storage},
                                                    sizeof(Push), gridSpec(config_)});
  forChunks(rows, params, "recordPositionGradient",
            [&](const gpu::BufferRange& in, const gpu::BufferRange& dF, Push p, uint32_t groups, uint32_t c,
                uint32_t chunkRows) {
              if (c == 0) limitedPosition_.begin(rec, rowLimit, rows.count, chunkRows, {kLocal});
              const gpu::BufferRange out = gpu::rowsOf(dPositions, 16, c * chunkRows, p.count);
              gpu::dispatchLimited(rec, *positionGradient_, {in, dF, exactly(params), out}, p,
                                   limitedPosition_.rows(c, 0), groups, "encode_hash_position_gradient");
            });
}

void HashEncoding::ensureSortScratch(uint64_t slots, uint64_t entries) {
  const uint32_t F = config_.featuresPerLevel;
  if (slots > slotCap_) {
    for (auto* b : {&slots_, &spanMax_, &spanAcc_})
      if (b->valid()) retired_.push_back(std::move(*b));
    const uint64_t chunks = gpu::groupsFor(slots, kChunk);
    slots_ = gpu::Buffer(ctx_, slots * slotBytes(F));
    spanMax_ = gpu::Buffer(ctx_, chunks * 4 * F);
    spanAcc_ = gpu::Buffer(ctx_, chunks * 8 * F);
    spanMax_.zero(), spanAcc_.zero();  // the reduce leaves them zeroed after every pass
    slotCap_ = slots;
  }
  if (entries > entryCap_) {
    for (auto* b : {&counts_, &cursor_})
      if (b->valid()) retired_.push_back(std::move(*b));
    if (scan_) retiredScans_.push_back(std::move(scan_));
    counts_ = gpu::Buffer(ctx_, entries * 4);
    cursor_ = gpu::Buffer(ctx_, entries * 4);
    scan_ = std::make_unique<gpu::PrefixSum>(ctx_, uint32_t(entries));
    entryCap_ = entries;
  }
}

// Passes over row ranges of the chunk and, within each, over ranges of levels, so that one pass
// sorts at most slotBudget_ contributions: count, prefix sum, scatter, then the three reduce
// stages (shaders/encoding/encode_hash_backward_*.comp). Rows outer, levels inner: each pass's entries are
// whole levels, so a pass's counts cover (levels << T) entries.
void HashEncoding::recordSortReduce(gpu::Recorder& rec, const gpu::BufferRange& positions,
                                    const gpu::BufferRange& dFeatures, const Push& p, const gpu::BufferRange& grads,
                                    const gpu::LimitedRows& limited) {
  const uint32_t L = config_.levels, T = config_.log2TableSize, F = config_.featuresPerLevel, n = p.count;
  const uint32_t rowsPerPass = std::min(n, slotBudget_ / 8);
  const uint64_t levelCap = std::max<uint64_t>(1, scanCapacity(ctx_) >> T);
  const uint32_t levelsPerPass =
      uint32_t(std::min<uint64_t>({L, std::max<uint64_t>(1, slotBudget_ / (8ull * rowsPerPass)), levelCap}));
  ensureSortScratch(uint64_t(rowsPerPass) * 8 * levelsPerPass, uint64_t(levelsPerPass) << T);
  SortPush sp{};
  sp.strideVec4 = p.strideVec4, sp.offsetVec4 = p.offsetVec4, sp.denseMask = p.denseMask;
  std::copy(std::begin(p.res), std::end(p.res), sp.res);
  sp.limitBase = limited.base;
  for (uint32_t r0 = 0; r0 < n; r0 += rowsPerPass) {
    sp.count = std::min(rowsPerPass, n - r0), sp.rowBase = r0;
    for (uint32_t l0 = 0; l0 < L; l0 += levelsPerPass) {
      sp.levelBegin = l0, sp.levelEnd = std::min(L, l0 + levelsPerPass);
      const uint32_t entries = (sp.levelEnd - l0) << T, slots = sp.count * 8 * (sp.levelEnd - l0);
      const gpu::BufferRange counts(counts_, 0, VkDeviceSize(entries) * 4), cursor(cursor_, 0, VkDeviceSize(entries) * 4);
      const gpu::BufferRange slotRange(slots_, 0, VkDeviceSize(slots) * slotBytes(F));
      rec.fill(counts_, 0, 0, VkDeviceSize(entries) * 4);
      rec.dispatch(count_, {positions, counts, limited.limit}, sp, gpu::groupsFor(sp.count, kLocal), 1, 1,
                   "encode_hash_backward_count");
      scan_->record(rec, counts, entries, cursor, entries);
      rec.dispatch(scatter_, {positions, dFeatures, cursor, slotRange, limited.limit}, sp,
                   gpu::groupsFor(sp.count, kLocal), 1, 1, "encode_hash_backward_scatter");
      const glsl::HashReducePush reducePush{slots, l0 << T, entries};
      const uint32_t groups = gpu::groupsFor(gpu::groupsFor(slots, kChunk), kLocal);
      for (auto& k : reduce_)
        rec.dispatch(k, {cursor, slotRange, exactly(grads), spanMax_, spanAcc_}, reducePush, groups, 1, 1,
                     "encode_hash_backward_reduce");
    }
  }
}

}  // namespace vknerf::nerf

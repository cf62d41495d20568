#include "nerf/network/mlp.h"

#include <algorithm>
#include <string>

#include "vknerf/error.h"
#include "network/mlp_nerf_head_shared.h"
#include "network/mlp_nerf_density_shared.h"
#include "network/mlp_nerf_fused_shared.h"
#include "network/mlp_nerf_head_backward_shared.h"
#include "network/mlp_sigmoid_backward_shared.h"

namespace vknerf::nerf {
namespace {

using HeadPush = glsl::MlpHeadPush;
using DensityPush = glsl::MlpDensityPush;
using FusedPush = glsl::MlpFusedPush;
using HeadBackwardPush = glsl::MlpHeadBackwardPush;
using SigmoidBackwardPush = glsl::MlpSigmoidBackwardPush;
using HeadSpec = glsl::MlpHeadSpec;
using DensitySpec = glsl::MlpDensitySpec;
using FusedSpec = glsl::MlpFusedSpec;
using HeadBackwardSpec = glsl::MlpHeadBackwardSpec;
using SigmoidBackwardSpec = glsl::MlpSigmoidBackwardSpec;

// MlpTuning's per-variant masks: bit 0 inference, bit 1 with the activations kept.
uint32_t variantBit(uint32_t mask, bool keep) { return (mask >> (keep ? 1 : 0)) & 1u; }

constexpr uint32_t kHeadLocal = 64;
constexpr uint32_t kInferenceRows = 16384;  // rows of the internal scratch used without a workspace

// Rows per chunk such that a matrix of `maxStride` floats per row fits one storage binding and one
// texel view.
uint32_t deviceChunkRows(const Context& ctx, uint32_t maxStride) {
  return gpu::rowsPerBinding(ctx, VkDeviceSize(maxStride) * 4, std::max<uint64_t>(maxStride / 4, 1));
}

gpu::Buffer rowsBuffer(Context& ctx, uint32_t rows, uint32_t stride) {
  return gpu::Buffer(ctx, std::max<VkDeviceSize>(VkDeviceSize(rows) * stride * 4, 16), "the MLP's activations");
}

core::NerfShape nerfShape(const MlpConfig& c) {
  try {
    return core::NerfShape::make(c.depth, c.width, c.skipLayer, c.posDims, c.dirDims, c.density, c.featureWidth);
  } catch (const std::invalid_argument& e) {
    throw Error(e.what());
  }
}

core::DenseMlpShape denseShape(const DenseMlpConfig& c) {
  try {
    return core::DenseMlpShape::make(c.inputs, c.width, c.hiddenLayers, c.outputs);
  } catch (const std::invalid_argument& e) {
    throw Error(e.what());
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------- NeRF

NerfMlp::Workspace::Workspace(Context& ctx, const NerfMlp& mlp, uint32_t capacity) : Workspace(ctx, mlp, capacity, true) {}

NerfMlp::Workspace::Workspace(Context& ctx, const NerfMlp& mlp, uint32_t capacity, bool keep)
    : capacity_(capacity), keep_(keep) {
  const uint32_t W = mlp.config_.width, V = mlp.shape_.featureWidth;
  uint32_t rows = std::max(capacity, 1u);
  for (uint32_t l = 0; l < (keep ? mlp.config_.depth : 2u); ++l) h_.push_back(rowsBuffer(ctx, rows, W));
  f_ = rowsBuffer(ctx, rows, V + 4);
  c_ = rowsBuffer(ctx, rows, W / 2);
  if (keep) {
    scratchRows_ = std::max(1u, std::min(capacity, mlp.chunkRows_));
    // dz_[0] holds dF (V + 4 per row), then the trunk's dZ (W), as does dz_[1].
    for (auto& b : dz_) b = rowsBuffer(ctx, scratchRows_, std::max(W, V + 4));
    dc_ = rowsBuffer(ctx, scratchRows_, W / 2);
    dzh_ = rowsBuffer(ctx, scratchRows_, 4);
  }
}

NerfMlp::NerfMlp(Context& ctx, const MlpConfig& config) : NerfMlp(ctx, config, MlpTuning::forDevice(ctx)) {}

NerfMlp::NerfMlp(Context& ctx, const MlpConfig& config, const MlpTuning& tuning)
    : ctx_(ctx), config_(config), shape_(nerfShape(config)), tuning_(tuning), limited_(ctx), limitedBackward_(ctx) {
  for (const auto& l : shape_.layers) layers_.emplace_back(ctx, l, tuning_);
  chunkRows_ = deviceChunkRows(ctx, std::max({posStride(), dirStride(), config.width + 4}));
}

std::vector<float> NerfMlp::initialParameters() const {
  return core::initialParameters(shape_.layers, shape_.total, config_.seed);
}

void NerfMlp::setChunkRows(uint32_t rows) {
  if (rows == 0 || rows % 64) throw Error("NeRF MLP: chunk rows must be a positive multiple of 64");
  chunkRows_ = std::min(rows, deviceChunkRows(ctx_, std::max({posStride(), dirStride(), config_.width + 4})));
  scratch_.reset();
}

bool NerfMlp::fusedForward(bool keep) const {
  // The multiply-adds an invocation's code spells out: a layer's K times its N when its output
  // blocks are unrolled, times one block's columns in the block loop (FUSED_BLOCK_FOR in
  // mlp_nerf_fused.comp: the tuning's block where it divides N, else 8 or 4).
  const bool unrolled = variantBit(tuning_.fusedUnroll, keep) != 0;
  uint64_t multiplyAdds = 0;
  for (const auto& l : shape_.layers) {
    const uint32_t n = l.n4(), block = n % tuning_.fusedBlock == 0 ? tuning_.fusedBlock : (n % 8 == 0 ? 8 : 4);
    multiplyAdds += uint64_t(l.k4()) * (unrolled ? n : block);
  }
  return variantBit(tuning_.fused, keep) && config_.skipLayer == 0 && config_.depth <= kMaxFusedDepth &&
         config_.width <= kMaxFusedWidth && multiplyAdds * tuning_.fusedRows <= kMaxFusedMultiplyAdds;
}

void NerfMlp::recordForward(gpu::Recorder& rec, const NerfRows& rows, const gpu::BufferRange& params,
                            Workspace* keep) {
  const uint32_t count = rows.count;
  const gpu::BufferRange &pos = rows.pos, &dir = rows.dir, &out = rows.out;
  const gpu::BufferRange* rowLimit = rows.rowLimit ? &*rows.rowLimit : nullptr;
  if (count == 0) return;
  if (rowLimit && gpu::boundBytes(*rowLimit) < 4) throw Error("NeRF MLP: row limit binding holds no uint");
  if (keep && keep->capacity_ < count)
    throw Error("NeRF MLP: workspace holds " + std::to_string(keep->capacity_) + " rows, batch has " + std::to_string(count));
  const gpu::BufferRange* rowGather = rows.rowGather ? &*rows.rowGather : nullptr;
  // The fused kernel has no row index, and its density-only variant keeps nothing: a gathered forward
  // and a kept density-only one go layer by layer.
  if (!rowGather && fusedForward(keep != nullptr) && !(keep && rows.densityOnly))
    return recordFusedForward(rec, rows, params, keep);
  Workspace& ws = keep ? *keep : inferenceScratch();
  const uint32_t W = config_.width, D = config_.depth, V = shape_.featureWidth;
  const uint32_t chunk = keep ? chunkRows_ : std::min(chunkRows_, ws.capacity_);
  if (rowGather && !keep) throw Error("NeRF MLP: a forward read through a row index keeps its activations");
  if (rowGather) gpu::requireGatherInOneChunk("NeRF MLP forward", *rowGather, count, chunk);
  const uint32_t colour = rows.densityOnly ? 0u : 1u;
  std::unique_ptr<gpu::Kernel>& headKernel = head_[colour];
  if (!headKernel) {
    const auto& h = shape_.head();
    headKernel = std::make_unique<gpu::Kernel>(
        ctx_, gpu::KernelDesc{gpu::shaders::mlp_nerf_head,
                              {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f,
                               gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                              sizeof(HeadPush),
                              {{HeadSpec::LOCAL_SIZE_X, kHeadLocal},
                               {HeadSpec::K4, h.ka4()},
                               {HeadSpec::WOFF4, uint32_t(h.offset / 4)},
                               {HeadSpec::SIGMA_COL, V},
                               {HeadSpec::DENSITY, uint32_t(config_.density)},
                               {HeadSpec::COLOUR, colour}}});
  }
  // Every dense layer has the same rows per workgroup (one tuning); the head has its own.
  limited_.begin(rec, rowLimit, count, chunk, {layers_[0].rowsPerGroup(), kHeadLocal});
  gpu::forRowChunks(count, chunk, [&](uint32_t first, uint32_t n, uint32_t c) {
    uint32_t row = keep ? first : 0;
    Mat p = Mat{pos, posStride()}.rows(first, n), d = Mat{dir, dirStride()}.rows(first, n);
    Mat o = Mat{out, 4}.rows(first, n);
    const gpu::LimitedRows L = limited_.rows(c, 0), head = limited_.rows(c, 1);
    Mat F = Mat{ws.f_, V + 4}.rows(row, n), C = Mat{ws.c_, W / 2}.rows(row, n);
    LayerRows layerRows{n, L};
    if (rowGather) layerRows.gather = *rowGather;  // one chunk: the gathered rows index the whole batch
    const Mat h = recordTrunk(rec, layerRows, params, p, ws, row);
    // The density alone needs sigma's column of the feature layer: its block of 4 from V.
    layers_[D].recordForward(rec, layerRows.as("nerf feature+sigma"), params, h, h, F, nullptr, rows.densityOnly ? V : 0);
    if (!rows.densityOnly) {
      const std::optional<RowBias> bias = rows.colourBias ? std::optional(rows.colourBias->rows(first, n)) : std::nullopt;
      layers_[D + 1].recordForward(rec, layerRows.as("nerf colour"), params, F, d, C, bias ? &*bias : nullptr);
    }
    gpu::dispatchLimited(rec, *headKernel, {C.range, F.range, params, o.range, rowGather ? *rowGather : o.range},
                         HeadPush{n, C.stride / 4, F.stride / 4, 1, 0, rowGather ? 1u : 0u}, head,
                         gpu::groupsFor(n, kHeadLocal), "nerf head");
  });
}

void NerfMlp::recordDensity(gpu::Recorder& rec, uint32_t count, const gpu::BufferRange& params,
                            const gpu::BufferRange& pos, const gpu::BufferRange& density) {
  if (count == 0) return;
  if (gpu::boundBytes(density) < VkDeviceSize(count) * 4)
    throw Error("NeRF MLP: the density buffer holds fewer than " + std::to_string(count) + " floats");
  Workspace& ws = inferenceScratch();
  const uint32_t W = config_.width, V = shape_.featureWidth;
  const core::DenseShape& feature = shape_.feature();
  if (!density_) {
    if (feature.kb != 0) throw Error("NeRF MLP: the density alone needs a feature layer with one input");
    density_ = std::make_unique<gpu::Kernel>(
        ctx_, gpu::KernelDesc{gpu::shaders::mlp_nerf_density,
                              {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f, gpu::Binding::Storage,
                               gpu::Binding::Storage},
                              sizeof(DensityPush),
                              {{DensitySpec::LOCAL_SIZE_X, tuning_.local},
                               {DensitySpec::R, tuning_.rows},
                               {DensitySpec::K4, feature.ka4()},
                               {DensitySpec::N4, feature.n4()},
                               {DensitySpec::V, V},
                               {DensitySpec::WOFF4, uint32_t(feature.offset / 4)},
                               {DensitySpec::DENSITY, uint32_t(config_.density)}}});
  }
  const uint32_t chunk = std::min(chunkRows_, ws.capacity_);
  const uint32_t rowsPerGroup = layers_[0].rowsPerGroup();  // the density kernel's too (same tuning)
  limited_.begin(rec, nullptr, count, chunk, {rowsPerGroup});
  gpu::forRowChunks(count, chunk, [&](uint32_t first, uint32_t n, uint32_t c) {
    const gpu::LimitedRows L = limited_.rows(c, 0);
    const Mat h = recordTrunk(rec, {n, L}, params, Mat{pos, posStride()}.rows(first, n), ws, 0);
    gpu::dispatchLimited(rec, *density_, {h.range, params, gpu::rowsOf(density, 4, first, n)},
                         DensityPush{n, W / 4, 0}, L, gpu::groupsFor(n, rowsPerGroup), "nerf density");
  });
}

NerfMlp::Workspace& NerfMlp::inferenceScratch() {
  if (!scratch_) scratch_.reset(new Workspace(ctx_, *this, std::min(chunkRows_, kInferenceRows), false));
  return *scratch_;
}

Mat NerfMlp::recordTrunk(gpu::Recorder& rec, const LayerRows& rows, const gpu::BufferRange& params, const Mat& pos,
                         Workspace& ws, uint32_t row) {
  // Kept activations: one buffer a layer; otherwise two, alternating.
  const uint32_t n = rows.count;
  auto H = [&](uint32_t l) { return Mat{ws.h_[ws.keep_ ? l : l % 2], config_.width}.rows(row, n); };
  for (uint32_t l = 0; l < config_.depth; ++l)
    layers_[l].recordForward(rec, rows.as("nerf trunk"), params, l ? H(l - 1) : pos, pos, H(l));
  return H(config_.depth - 1);
}

void NerfMlp::recordFusedForward(gpu::Recorder& rec, const NerfRows& rows, const gpu::BufferRange& params,
                                 Workspace* keep) {
  const uint32_t count = rows.count;
  const gpu::BufferRange &pos = rows.pos, &dir = rows.dir, &out = rows.out;
  const gpu::BufferRange* rowLimit = rows.rowLimit ? &*rows.rowLimit : nullptr;
  const uint32_t W = config_.width, D = config_.depth, V = shape_.featureWidth;
  const bool densityOnly = rows.densityOnly;  // recordForward sent a kept density-only forward layer by layer
  const uint32_t mode = rowBiasMode(rows.colourBias && !densityOnly ? &*rows.colourBias : nullptr);
  auto& kernel = densityOnly ? fusedDensity_ : fused_[keep ? 1 : 0][mode];
  if (!kernel) {
    auto off4 = [&](const core::DenseShape& l) { return uint32_t(l.offset / 4); };
    std::vector<gpu::Binding> b(3, gpu::Binding::TexelRgba32f);
    b.insert(b.end(), 5, gpu::Binding::Storage);
    b.insert(b.end(), {gpu::Binding::TexelRgba32f, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage});
    kernel = std::make_unique<gpu::Kernel>(
        ctx_, gpu::KernelDesc{gpu::shaders::mlp_nerf_fused, b, sizeof(FusedPush),
                              {{FusedSpec::LOCAL_SIZE_X, tuning_.local},
                               {FusedSpec::R, tuning_.fusedRows},
                               {FusedSpec::KP4, posStride()},
                               {FusedSpec::KD4, dirStride()},
                               {FusedSpec::W, W},
                               {FusedSpec::DEPTH, D},
                               {FusedSpec::V, V},
                               {FusedSpec::DENSITY, uint32_t(config_.density)},
                               {FusedSpec::KEEP, keep ? 1u : 0u},
                               {FusedSpec::NB, tuning_.fusedBlock},
                               {FusedSpec::T0OFF4, off4(shape_.trunk(0))},
                               {FusedSpec::T1OFF4, off4(shape_.trunk(D > 1 ? 1 : 0))},
                               {FusedSpec::FOFF4, off4(shape_.feature())},
                               {FusedSpec::COFF4, off4(shape_.colour())},
                               {FusedSpec::HOFF4, off4(shape_.head())},
                               {FusedSpec::UNROLL, variantBit(tuning_.fusedUnroll, keep)},
                               {FusedSpec::ROW_BIAS, mode},
                               {FusedSpec::COLOUR, densityOnly ? 0u : 1u}}});
  }
  // The rows of one chunk bind within the device's limits; nothing lives between layers, so a batch
  // without a workspace needs no scratch rows either.
  const uint32_t rowsPerGroup = tuning_.local * tuning_.fusedRows;
  limited_.begin(rec, rowLimit, count, chunkRows_, {rowsPerGroup});
  gpu::forRowChunks(count, chunkRows_, [&](uint32_t first, uint32_t n, uint32_t c) {
    Mat p = Mat{pos, posStride()}.rows(first, n), d = Mat{dir, dirStride()}.rows(first, n);
    Mat o = Mat{out, 4}.rows(first, n);
    // Without a workspace the kept-activation bindings are never written: any buffer will do.
    auto kept = [&](const gpu::Buffer& b, uint32_t stride) { return Mat{b, stride}.rows(first, n).range; };
    const gpu::BufferRange none = o.range;
    FusedPush push{n, p.stride / 4, d.stride / 4, 1, 0};
    const std::optional<RowBias> chunkBias =
        rows.colourBias && !densityOnly ? std::optional(rows.colourBias->rows(first, n)) : std::nullopt;
    const auto bias = rowBiasBindings(chunkBias ? &*chunkBias : nullptr, params);
    gpu::dispatchLimited(rec, *kernel,
                         {p.range, d.range, params, o.range, keep ? kept(keep->h_[0], W) : none,
                          keep && D > 1 ? kept(keep->h_[1], W) : none, keep ? kept(keep->f_, V + 4) : none,
                          keep ? kept(keep->c_, W / 2) : none, bias[0], bias[1], bias[2]},
                         push, limited_.rows(c, 0), gpu::groupsFor(n, rowsPerGroup), "nerf mlp fused");
  });
}

void NerfMlp::recordBackward(gpu::Recorder& rec, const NerfRows& rows, const gpu::BufferRange& params,
                             const NerfGradients& gradients, Workspace& ws) {
  const uint32_t count = rows.count;
  const gpu::BufferRange &pos = rows.pos, &dir = rows.dir, &out = rows.out;
  const gpu::BufferRange* rowLimit = rows.rowLimit ? &*rows.rowLimit : nullptr;
  const gpu::BufferRange &dOut = gradients.dOut, &grads = gradients.grads;
  const gpu::BufferRange* dPos = gradients.dPos ? &*gradients.dPos : nullptr;
  const gpu::BufferRange* rowGather = gradients.rowGather ? &*gradients.rowGather : nullptr;
  const gpu::BufferRange* dDir = gradients.dDir ? &*gradients.dDir : nullptr;
  if (count == 0) return;
  if (rowLimit && gpu::boundBytes(*rowLimit) < 4) throw Error("NeRF MLP: row limit binding holds no uint");
  if (dDir) gpu::requireBytes("NeRF MLP backward", "dDir", *dDir, uint64_t(count) * dirStride() * 4);
  const gpu::BufferRange* dColour = gradients.dColour ? &*gradients.dColour : nullptr;
  if (dColour) gpu::requireBytes("NeRF MLP backward", "dColour", *dColour, uint64_t(count) * (config_.width / 2) * 4);
  if (!ws.keep_ || ws.capacity_ < count)
    throw Error("NeRF MLP: backward needs the workspace of a forward pass over at least " + std::to_string(count) + " rows");
  if (rows.densityOnly && (dDir || dColour))
    throw Error("NeRF MLP: a density-only backward gives no direction or colour-layer gradient");
  const uint32_t W = config_.width, D = config_.depth, V = shape_.featureWidth;
  const uint32_t colour = rows.densityOnly ? 0u : 1u;
  std::unique_ptr<gpu::Kernel>& headKernel = headBackward_[colour];
  if (!headKernel) {
    const auto& h = shape_.head();
    std::vector<gpu::Binding> b(5, gpu::Binding::TexelRgba32f);
    b.insert(b.end(), 5, gpu::Binding::Storage);
    headKernel = std::make_unique<gpu::Kernel>(
        ctx_, gpu::KernelDesc{gpu::shaders::mlp_nerf_head_backward, b, sizeof(HeadBackwardPush),
                              {{HeadBackwardSpec::LOCAL_SIZE_X, kHeadLocal},
                               {HeadBackwardSpec::K4, h.ka4()},
                               {HeadBackwardSpec::WOFF4, uint32_t(h.offset / 4)},
                               {HeadBackwardSpec::SIGMA_COL, V},
                               {HeadBackwardSpec::DENSITY, uint32_t(config_.density)},
                               {HeadBackwardSpec::COLOUR, colour}}});
  }
  const uint32_t chunk = std::min(chunkRows_, ws.scratchRows_);
  if (rowGather) gpu::requireGatherInOneChunk("NeRF MLP backward", *rowGather, count, chunk);
  // Every dense layer has the same rows per workgroup (one tuning); the head has its own.
  limitedBackward_.begin(rec, rowLimit, count, chunk, {layers_[0].dxRowsPerGroup(), kHeadLocal});
  gpu::forRowChunks(count, chunk, [&](uint32_t first, uint32_t n, uint32_t c) {
    const gpu::LimitedRows L = limitedBackward_.rows(c, 0), head = limitedBackward_.rows(c, 1);
    Mat p = Mat{pos, posStride()}.rows(first, n), d = Mat{dir, dirStride()}.rows(first, n);
    Mat o = Mat{out, 4}.rows(first, n), dO = Mat{dOut, 4}.rows(first, n);
    auto H = [&](uint32_t l) { return Mat{ws.h_[l], W}.rows(first, n); };
    Mat F = Mat{ws.f_, V + 4}.rows(first, n), C = Mat{ws.c_, W / 2}.rows(first, n);
    Mat dzh = Mat{ws.dzh_, 4}.rows(0, n), dF = Mat{ws.dz_[0], V + 4}.rows(0, n);
    // The colour layer's pre-activation gradient: the caller's rows when it wants them, else scratch.
    Mat dC = dColour ? Mat{*dColour, W / 2}.rows(first, n) : Mat{ws.dc_, W / 2}.rows(0, n);
    Mat dP = dPos ? Mat{*dPos, posStride()}.rows(first, n) : p;
    Mat dD = dDir ? Mat{*dDir, dirStride()}.rows(first, n) : d;

    const gpu::BufferRange* gather = rowGather;  // one chunk: the gathered rows index the whole batch
    HeadBackwardPush hp{n, 1, 1, C.stride / 4, F.stride / 4, dF.stride / 4, dC.stride / 4, gather ? 1u : 0u, 0};
    gpu::dispatchLimited(rec, *headKernel,
                         {dO.range, o.range, C.range, F.range, params, dzh.range, dF.range, dC.range,
                          gather ? *gather : dzh.range},
                         hp, head, gpu::groupsFor(n, kHeadLocal), "nerf head backward");
    LayerRows layerRows{n, L};
    if (gather) layerRows.gather = *gather;
    // After a density-only forward the head wrote sigma's block of dF alone: the colour branch has no
    // gradient, and the feature layer's backward reads dF from column V on (the rest is 0).
    const uint32_t firstF = rows.densityOnly ? V : 0;
    if (!rows.densityOnly) {
      layers_[D + 2].recordBackwardWeights(rec, layerRows.as("nerf head dW"), C, C, dzh, grads);
      layers_[D + 1].recordBackwardWeights(rec, layerRows.as("nerf colour dW"), F, d, dC, grads);
      layers_[D + 1].recordBackwardInput(
          rec, layerRows.as("nerf colour dX"), params, dC, F,
          {GradMode::Store, dF, dDir ? GradMode::Store : GradMode::Skip, dD, gradients.dDirFirst});
    }
    layers_[D].recordBackwardWeights(rec, layerRows.as("nerf feature+sigma dW"), H(D - 1), H(D - 1), dF, grads, firstF);
    Mat cur = Mat{ws.dz_[1], W}.rows(0, n), other = Mat{ws.dz_[0], W}.rows(0, n);
    layers_[D].recordBackwardInput(rec, layerRows.as("nerf feature+sigma dX"), params, dF, H(D - 1),
                                   {GradMode::StoreReluMasked, cur}, firstF);
    for (uint32_t l = D; l-- > 0;) {
      Mat a = l ? H(l - 1) : p;
      layers_[l].recordBackwardWeights(rec, layerRows.as("nerf trunk dW"), a, p, cur, grads);
      if (l > 0) {
        layers_[l].recordBackwardInput(rec, layerRows.as("nerf trunk dX"), params, cur, a,
                                       {GradMode::StoreReluMasked, other, dPos ? GradMode::Store : GradMode::Skip, dP});
        std::swap(cur, other);
      } else if (dPos) {
        layers_[0].recordBackwardInput(rec, layerRows.as("nerf trunk dX"), params, cur, a,
                                       {config_.skipLayer ? GradMode::Add : GradMode::Store, dP});
      }
    }
  });
}

// ---------------------------------------------------------------------------------------------- plain

DenseMlp::Workspace::Workspace(Context& ctx, const DenseMlp& mlp, uint32_t capacity) : Workspace(ctx, mlp, capacity, true) {}

DenseMlp::Workspace::Workspace(Context& ctx, const DenseMlp& mlp, uint32_t capacity, bool keep)
    : capacity_(capacity), keep_(keep) {
  const uint32_t W = mlp.config_.width;
  uint32_t rows = std::max(capacity, 1u);
  uint32_t hidden = mlp.config_.hiddenLayers;
  for (uint32_t l = 0; l < (keep ? hidden : std::min(hidden, 2u)); ++l) h_.push_back(rowsBuffer(ctx, rows, W));
  if (keep) {
    scratchRows_ = std::max(1u, std::min(capacity, mlp.chunkRows_));
    for (auto& b : dz_) b = rowsBuffer(ctx, scratchRows_, W);
    dzOut_ = rowsBuffer(ctx, scratchRows_, mlp.outputStride());
  }
}

DenseMlp::DenseMlp(Context& ctx, const DenseMlpConfig& config) : DenseMlp(ctx, config, MlpTuning::forDevice(ctx)) {}

DenseMlp::DenseMlp(Context& ctx, const DenseMlpConfig& config, const MlpTuning& tuning)
    : ctx_(ctx), config_(config), shape_(denseShape(config)), tuning_(tuning), uncut_(ctx) {
  for (const auto& l : shape_.layers) layers_.emplace_back(ctx, l, tuning_);
  chunkRows_ = deviceChunkRows(ctx, std::max({inputStride(), outputStride(), config.width}));
}

std::vector<float> DenseMlp::initialParameters() const {
  return core::initialParameters(shape_.layers, shape_.total, config_.seed);
}

void DenseMlp::setChunkRows(uint32_t rows) {
  if (rows == 0 || rows % 64) throw Error("dense MLP: chunk rows must be a positive multiple of 64");
  chunkRows_ = std::min(rows, deviceChunkRows(ctx_, std::max({inputStride(), outputStride(), config_.width})));
  scratch_.reset();
}

void DenseMlp::recordForward(gpu::Recorder& rec, const DenseRows& rows, const gpu::BufferRange& params,
                             Workspace* keep) {
  const uint32_t count = rows.count;
  const gpu::BufferRange &in = rows.in, &out = rows.out;
  if (count == 0) return;
  if (keep && keep->capacity_ < count)
    throw Error("dense MLP: workspace holds " + std::to_string(keep->capacity_) + " rows, batch has " + std::to_string(count));
  if (!keep && !scratch_) scratch_.reset(new Workspace(ctx_, *this, std::min(chunkRows_, kInferenceRows), false));
  Workspace& ws = keep ? *keep : *scratch_;
  const uint32_t chunk = keep ? chunkRows_ : std::min(chunkRows_, scratch_->capacity_);
  const uint32_t L = uint32_t(layers_.size());
  gpu::forRowChunks(count, chunk, [&](uint32_t first, uint32_t n, uint32_t) {
    uint32_t row = keep ? first : 0;
    auto H = [&](uint32_t l) { return Mat{ws.h_[ws.keep_ ? l : l % 2], config_.width}.rows(row, n); };
    Mat x = Mat{in, inputStride()}.rows(first, n), y = Mat{out, outputStride()}.rows(first, n);
    for (uint32_t l = 0; l < L; ++l) {
      Mat a = l ? H(l - 1) : x;
      layers_[l].recordForward(rec, {n, uncut_.uncut(), {}, "mlp forward"}, params, a, a, l + 1 < L ? H(l) : y);
    }
  });
}

void DenseMlp::recordBackward(gpu::Recorder& rec, const DenseRows& rows, const gpu::BufferRange& params,
                              const DenseGradients& gradients, Workspace& ws) {
  const uint32_t count = rows.count;
  const gpu::BufferRange &in = rows.in, &out = rows.out, &dOut = gradients.dOut, &grads = gradients.grads;
  const gpu::BufferRange* dIn = gradients.dIn ? &*gradients.dIn : nullptr;
  if (count == 0) return;
  if (!ws.keep_ || ws.capacity_ < count)
    throw Error("dense MLP: backward needs the workspace of a forward pass over at least " + std::to_string(count) + " rows");
  if (!sigmoidBackward_)
    sigmoidBackward_ = std::make_unique<gpu::Kernel>(
        ctx_, gpu::KernelDesc{gpu::shaders::mlp_sigmoid_backward,
                              {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f, gpu::Binding::Storage},
                              sizeof(SigmoidBackwardPush),
                              {{SigmoidBackwardSpec::N4, outputStride()}, {SigmoidBackwardSpec::NTRUE, config_.outputs}}});
  const uint32_t W = config_.width, L = uint32_t(layers_.size());
  gpu::forRowChunks(count, std::min(chunkRows_, ws.scratchRows_), [&](uint32_t first, uint32_t n, uint32_t) {
    auto H = [&](uint32_t l) { return Mat{ws.h_[l], W}.rows(first, n); };
    Mat x = Mat{in, inputStride()}.rows(first, n);
    Mat y = Mat{out, outputStride()}.rows(first, n), dy = Mat{dOut, outputStride()}.rows(first, n);
    Mat cur = Mat{ws.dzOut_, outputStride()}.rows(0, n);
    SigmoidBackwardPush sp{n, dy.stride / 4, y.stride / 4, cur.stride / 4};
    rec.dispatchFlat(*sigmoidBackward_, {dy.range, y.range, cur.range}, sp, uint64_t(n) * (outputStride() / 4), 64,
                     "mlp output backward");
    int next = 0;
    for (uint32_t l = L; l-- > 0;) {
      Mat a = l ? H(l - 1) : x;
      const LayerRows rows{n, uncut_.uncut()};
      layers_[l].recordBackwardWeights(rec, rows.as("mlp dW"), a, a, cur, grads);
      if (l > 0) {
        Mat da = Mat{ws.dz_[next], W}.rows(0, n);
        layers_[l].recordBackwardInput(rec, rows.as("mlp dX"), params, cur, a, {GradMode::StoreReluMasked, da});
        cur = da;
        next ^= 1;
      } else if (dIn) {
        Mat d = Mat{*dIn, inputStride()}.rows(first, n);
        layers_[0].recordBackwardInput(rec, rows.as("mlp dX"), params, cur, a, {GradMode::Store, d});
      }
    }
  });
}

}  // namespace vknerf::nerf

#pragma once
// The NeRF MLP (seed §4.8) and a plain MLP, batched on the device, forward and backward.
//
// Layouts (per sample = per row, row-major, row strides in floats, multiples of 4):
//   posFeatures gamma(x): posStride() = pad4(posDims) floats per row, padding columns zero
//   dirFeatures gamma(d): dirStride() = pad4(dirDims)
//   out:  vec4 (r, g, b, sigma) per row, rgb after sigmoid, sigma after the density activation
//   dOut: vec4 dL/d(r, g, b, sigma) per row
//   params: ONE flat float buffer, parameterCount() floats, layout in src/core/layouts/mlp_layout.h (each
//           layer W row-major [ka4 + kb4][n4] then bias [n4]; padding entries zero and never updated)
//   grads:  same size as params. recordBackward ACCUMULATES into it (atomics, in any order): zero it
//           first (e.g. Recorder::fill) once per step.
// Batches of any size (0 included) are split into chunks whose bindings stay within the device's
// maxStorageBufferRange / maxTexelBufferElements; buffers are bound at row offsets.
#include <memory>
#include <optional>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/network/dense_layer.h"
#include "core/layouts/mlp_layout.h"

namespace vknerf::nerf {

struct MlpConfig {
  uint32_t depth = 8;       // trunk layers
  uint32_t width = 256;     // trunk width W (multiple of 8); the colour layer is W/2 wide
  uint32_t skipLayer = 5;   // trunk layer whose input is concat(h, gamma(x)); 0: none (paper: 5)
  uint32_t posDims = 63;
  uint32_t dirDims = 27;
  DensityActivation density = DensityActivation::Relu;
  uint32_t seed = 0;
  uint32_t featureWidth = 0;  // what the colour layer sees of the feature layer (0: width); core::NerfShape
};

// The rows a NeRF MLP runs over, as one value: `count` rows of pos (posStride() floats each), dir
// (dirStride()) and out (vec4). rowLimit (optional): a uint on the device (e.g. a sample total);
// only rows below it are computed, the rest of `out` is left untouched (shaders/gpu/row_limit.glsl).
// colourBias (optional): a bias per row added to the colour layer's pre-activation (W/2 floats a
// table row; its rowRay, when given, holds `count` rows): what an input beside the direction that is
// the same for many rows (a per-photo appearance vector a, through its weights: a W_a) adds, without
// widening the layer.
struct NerfRows {
  uint32_t count = 0;
  gpu::BufferRange pos, dir, out;
  std::optional<gpu::BufferRange> rowLimit;
  std::optional<RowBias> colourBias;
  // The forward alone, with kept activations, in one chunk: row i of the batch is row rowGather[i]
  // of pos, dir, out, the activations and the colour bias (a uint per row); the other rows are left.
  std::optional<gpu::BufferRange> rowGather;
  // Only the density is read and trained (a proposal's weights): the colour branch is skipped and
  // out's rgb written 0; dir and colourBias are not read. A forward that keeps its activations keeps
  // the trunk's and the feature layer's sigma block (its 4 columns from featureWidth; the feature
  // columns are not computed), and its backward must be given densityOnly too: it reads dOut's sigma
  // alone (rgb taken as 0, unread), leaves the gradients of the colour layer, the head and the
  // feature layer's feature columns as they are (they would be exactly 0) and takes no dDir or dColour.
  bool densityOnly = false;
};

// What a NeRF MLP's backward reads and writes besides the forward's rows: dOut (vec4 per row), the
// parameter gradients it accumulates into, dPos (optional, posStride() per row) = dL/dgamma(x),
// overwritten; dDir (optional, dirStride() per row) = dL/d(the direction input), overwritten (the
// colour layer's input gradient: what an input learned beside the direction, such as a per-photo
// appearance vector, trains from); rowGather (optional, uint per row): the batch is packed, its row i the forward's row
// rowGather[i] (pos, dir, out, dOut and the activations are read there; the rows early termination
// cut need not be computed), and dPos and dDir are written packed (row i).
// dColour (optional, W/2 floats per row) = dL/d(the colour layer's pre-activation), overwritten
// (packed like dDir): the gradient of a bias per row (NerfRows::colourBias).
struct NerfGradients {
  gpu::BufferRange dOut, grads;
  std::optional<gpu::BufferRange> dPos, rowGather, dDir, dColour;
  uint32_t dDirFirst = 0;  // dDir's columns before it (a multiple of 4) are neither computed nor written
};

class NerfMlp {
 public:
  // Activations of a forward pass, kept for backward (capacity rows), plus backward scratch.
  class Workspace {
   public:
    Workspace(Context& ctx, const NerfMlp& mlp, uint32_t capacity);
    uint32_t capacity() const { return capacity_; }

   private:
    friend class NerfMlp;
    Workspace(Context& ctx, const NerfMlp& mlp, uint32_t capacity, bool keep);
    uint32_t capacity_ = 0, scratchRows_ = 0;
    bool keep_ = true;
    std::vector<gpu::Buffer> h_;  // trunk outputs (depth buffers, or 2 reused when !keep_)
    gpu::Buffer f_, c_;           // feature + sigma pre-activation (V + 4), colour hidden (W/2)
    gpu::Buffer dz_[2], dc_, dzh_;  // backward scratch, scratchRows_ rows
  };

  NerfMlp(Context& ctx, const MlpConfig& config);
  NerfMlp(Context& ctx, const MlpConfig& config, const MlpTuning& tuning);

  const MlpConfig& config() const { return config_; }
  const core::NerfShape& shape() const { return shape_; }
  size_t parameterCount() const { return shape_.total; }
  std::vector<float> initialParameters() const;
  uint32_t posStride() const { return core::pad4(config_.posDims); }
  uint32_t dirStride() const { return core::pad4(config_.dirDims); }

  // out = f(pos, dir) over `rows`. With a workspace (capacity >= rows.count) the activations are kept
  // for recordBackward; without one an internal scratch is used and nothing is kept. Rows at and
  // past rows.rowLimit are not computed.
  void recordForward(gpu::Recorder& rec, const NerfRows& rows, const gpu::BufferRange& params,
                     Workspace* keepForBackward);
  // density[i] = the density of row i (after the density activation), one float a row: the trunk
  // and the feature layer's sigma column only (mlp_nerf_density.comp), for callers that need no
  // colour (the occupancy update). The same sums as recordForward's sigma; uses the internal
  // scratch, as recordForward without a workspace does.
  void recordDensity(gpu::Recorder& rec, uint32_t count, const gpu::BufferRange& params, const gpu::BufferRange& pos,
                     const gpu::BufferRange& density);
  // grads.grads += dL/dparams for the batch last run forward into `ws` (rows.out: what that forward
  // wrote). The rows at and past rows.rowLimit add nothing to grads and leave dPos untouched. A
  // gathered batch (grads.rowGather) must fit one chunk (rows.count <= chunkRows()).
  void recordBackward(gpu::Recorder& rec, const NerfRows& rows, const gpu::BufferRange& params,
                      const NerfGradients& grads, Workspace& ws);

  // Rows per chunk (derived from device limits). Tests lower it to exercise chunking cheaply;
  // set it before creating workspaces.
  uint32_t chunkRows() const { return chunkRows_; }
  void setChunkRows(uint32_t rows);

  // Whether the forward, with the activations kept or not, runs as one kernel (mlp_nerf_fused.comp):
  // a network without a skip connection (the fast model's) of at most kMaxFusedDepth trunk layers of
  // at most kMaxFusedWidth, where the tuning asks for it (MlpTuning::fused). Its activations live
  // in registers, which bounds the widths, and its layers may be unrolled (MlpTuning::fusedUnroll):
  // the multiply-adds an invocation's code spells out (rows x the padded layers' K x N unrolled,
  // K x one block of columns in the block loop) are held to kMaxFusedMultiplyAdds, since the
  // driver's compile time grows faster than the code (on lavapipe the fast model's 8 x 3456,
  // unrolled, take ~45 s once, then come from Mesa's disk cache; 8 x 8064, its network with a
  // 64-wide feature, took minutes). Larger networks run layer by layer.
  static constexpr uint32_t kMaxFusedDepth = 2, kMaxFusedWidth = 64, kMaxFusedMultiplyAdds = 32768;
  bool fusedForward(bool keep) const;

 private:
  Workspace& inferenceScratch();  // the activations of a forward without a workspace
  // The trunk over rows [row, row + n) of ws's activations (pos: those rows' encodings); returns
  // the last trunk layer's output.
  Mat recordTrunk(gpu::Recorder& rec, const LayerRows& rows, const gpu::BufferRange& params, const Mat& pos,
                  Workspace& ws, uint32_t row);
  void recordFusedForward(gpu::Recorder& rec, const NerfRows& rows, const gpu::BufferRange& params, Workspace* keep);

  Context& ctx_;
  MlpConfig config_;
  core::NerfShape shape_;
  MlpTuning tuning_;
  std::vector<DenseLayer> layers_;  // trunk, feature, colour (the head has its own kernels)
  // The head's kernels, by COLOUR: [0] the density alone (NerfRows::densityOnly), [1] the whole head.
  std::unique_ptr<gpu::Kernel> head_[2], headBackward_[2];
  std::unique_ptr<gpu::Kernel> density_;
  std::unique_ptr<gpu::Kernel> fused_[2][3];  // the fused forward without / with the activations kept, by ROW_BIAS_*
  std::unique_ptr<gpu::Kernel> fusedDensity_;  // the fused forward of the density alone (NerfRows::densityOnly)
  gpu::LimitedDispatch limited_;          // the forward's workgroup counts under a row limit
  gpu::LimitedDispatch limitedBackward_;  // the backward's
  std::unique_ptr<Workspace> scratch_;
  uint32_t chunkRows_ = 0;
};

// The rows a plain MLP runs over: `count` rows of in (inputStride() floats each) and out (outputStride()).
struct DenseRows {
  uint32_t count = 0;
  gpu::BufferRange in, out;
};

// What a plain MLP's backward reads and writes besides the forward's rows: dOut (outputStride() per
// row), the parameter gradients it accumulates into, and dIn (optional, inputStride() per row) =
// dL/din, overwritten.
struct DenseGradients {
  gpu::BufferRange dOut, grads;
  std::optional<gpu::BufferRange> dIn;
};

struct DenseMlpConfig {
  uint32_t inputs = 2, width = 128, hiddenLayers = 2, outputs = 3;
  uint32_t seed = 0;
};

// inputs -> hiddenLayers x (Linear(width) + ReLU) -> Linear(outputs) + sigmoid.
// in: inputStride() = pad4(inputs) floats per row; out: outputStride() = pad4(outputs), padding 0.
class DenseMlp {
 public:
  class Workspace {
   public:
    Workspace(Context& ctx, const DenseMlp& mlp, uint32_t capacity);
    uint32_t capacity() const { return capacity_; }

   private:
    friend class DenseMlp;
    Workspace(Context& ctx, const DenseMlp& mlp, uint32_t capacity, bool keep);
    uint32_t capacity_ = 0, scratchRows_ = 0;
    bool keep_ = true;
    std::vector<gpu::Buffer> h_;   // hidden outputs
    gpu::Buffer dz_[2], dzOut_;    // backward scratch
  };

  DenseMlp(Context& ctx, const DenseMlpConfig& config);
  DenseMlp(Context& ctx, const DenseMlpConfig& config, const MlpTuning& tuning);

  const core::DenseMlpShape& shape() const { return shape_; }
  size_t parameterCount() const { return shape_.total; }
  std::vector<float> initialParameters() const;
  uint32_t inputStride() const { return core::pad4(config_.inputs); }
  uint32_t outputStride() const { return core::pad4(config_.outputs); }

  void recordForward(gpu::Recorder& rec, const DenseRows& rows, const gpu::BufferRange& params,
                     Workspace* keepForBackward);
  // grads.grads += dL/dparams for the batch last run forward into `ws`; grads.dIn = dL/din.
  void recordBackward(gpu::Recorder& rec, const DenseRows& rows, const gpu::BufferRange& params,
                      const DenseGradients& grads, Workspace& ws);

  uint32_t chunkRows() const { return chunkRows_; }
  void setChunkRows(uint32_t rows);

 private:
  Context& ctx_;
  DenseMlpConfig config_;
  core::DenseMlpShape shape_;
  MlpTuning tuning_;
  std::vector<DenseLayer> layers_;
  gpu::LimitedDispatch uncut_;  // the layers' placeholder row limit: this network is never cut
  std::unique_ptr<gpu::Kernel> sigmoidBackward_;
  std::unique_ptr<Workspace> scratch_;
  uint32_t chunkRows_ = 0;
};

}  // namespace vknerf::nerf

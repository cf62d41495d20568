#pragma once
// One dense layer y = act(concat(a, b) W + bias) on the device: forward (mlp_dense.comp), backward to
// the inputs (mlp_dense_dx.comp) and to the weights (mlp_dense_dw*.comp). The networks in
// nerf/network/mlp.h are sequences of these. Kernels are built on first use, so a forward-only user never
// pays the JIT time of the backward pipelines.
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/limited_dispatch.h"
#include "gpu/dispatch/recorder.h"
#include "gpu/kernels/shader_code.h"
#include "core/layouts/mlp_layout.h"

namespace vknerf::nerf {

// Work shapes of the MLP kernels (specialization constants): lavapipe wants lanes = rows with
// several rows per invocation; GPUs want one row per lane and many lanes.
struct MlpTuning {
  uint32_t local = 64;       // invocations per workgroup, row-parallel kernels
  uint32_t rows = 4;         // rows per invocation, forward
  uint32_t block = 8;        // output columns per block, forward (multiple of 4)
  uint32_t dxRows = 4;       // rows per invocation, input gradient
  uint32_t dxBlock = 8;      // input columns per block, input gradient (multiple of 4)
  uint32_t dwLocal = 64;     // invocations per workgroup, weight gradient
  uint32_t dwKT = 16, dwNT = 16;  // weight-gradient tile per invocation (multiples of 4)
  uint32_t dwU = 2;          // rows summed per loop iteration
  uint32_t dwRows = 512;     // rows per invocation (a multiple of dwU)
  // How the weight gradient reduces and adds (network/mlp_dense_dw.glsl): 1: float atomicAdd, 0: a
  // compare-and-swap loop; 1: subgroupAdd first, 0: a workgroup reduction in shared memory.
  // forDevice takes them from the device (nerf/network/gradient_paths.h); tests set each.
  uint32_t dwFloatAtomics = 1, dwSubgroup = 1;
  // Bit 0: a narrow NeRF MLP's inference (rendering, exporters' queries) runs as one kernel
  // (mlp_nerf_fused.comp), bit 1: its forward with the activations kept (training) too. On
  // lavapipe the fused inference is ~1.35x faster than the layers; with the activations kept it
  // was no faster, so training stays layered (docs/performance.md).
  uint32_t fused = 1;
  uint32_t fusedRows = 8;    // rows per invocation, fused forward
  uint32_t fusedBlock = 4;   // output columns per block, fused forward (multiple of 4)
  // Bit 0: unroll the fused forward's output blocks for inference, bit 1: when keeping activations.
  // On lavapipe unrolling makes inference another ~1.45x faster, but its first compile takes ~45 s
  // and ~190 MB on a fresh machine, and loading it from Mesa's cache ~1.2 s a process: it pays
  // only for long renders, so it is off by default (docs/performance.md).
  uint32_t fusedUnroll = 0;
  static MlpTuning forDevice(const Context& ctx);
};

// A row-major matrix in a buffer: `stride` floats per row (multiple of 4).
struct Mat {
  gpu::BufferRange range;
  uint32_t stride = 0;
  // Rows [first, first + count) as their own binding (chunks stay within maxStorageBufferRange).
  Mat rows(uint32_t first, uint32_t count) const;
};

// A bias per row added to a layer's pre-activation before its activation (shaders/network/row_bias.glsl):
// row r adds row t(r) of `table` (n4 floats a row), t(r) = rayTable[rowRay[r]].x where both are given
// (uint per row: the row's sample's ray; uvec2 per ray: its photo first), else 0 for every row.
struct RowBias {
  gpu::BufferRange table;
  std::optional<gpu::BufferRange> rowRay, rayTable;
  // The same bias for rows [first, first + n) of the batch (a chunk bound at its first row).
  RowBias rows(uint32_t first, uint32_t n) const;
};
// The kernels' ROW_BIAS_* mode for `bias` (none: ROW_BIAS_NONE), and its three bindings (`unused`
// stands in for those the mode never reads).
uint32_t rowBiasMode(const RowBias* bias);
std::array<gpu::BufferRange, 3> rowBiasBindings(const RowBias* bias, const gpu::BufferRange& unused);

// The weight-gradient module for the tuning's dwFloatAtomics and dwSubgroup.
const gpu::ShaderCode& weightGradientShader(const MlpTuning& tuning);

enum class GradMode : uint32_t { Skip = 0, Store = 1, StoreReluMasked = 2, Add = 3 };

// The rows one layer call runs over, as one value: `count` rows, uncut or cut on the device to a
// limit (gpu/dispatch/limited_dispatch.h) whose arguments were recorded for the call's rows per workgroup;
// `gather` (backward only, uint per row): row i reads the forward's activations at row gather[i]
// (a packed batch, shaders/gpu/row_gather.glsl); `label` names the dispatches.
struct LayerRows {
  uint32_t count = 0;
  gpu::LimitedRows limited;
  std::optional<gpu::BufferRange> gather;
  const char* label = "mlp";
  // The same rows under another label.
  LayerRows as(const char* name) const {
    LayerRows r = *this;
    r.label = name;
    return r;
  }
};

// Where a layer's input gradients go (recordBackwardInput): da for input a (ka4 columns), db for
// input b (kb4 columns), each per its GradMode; a skipped one needs no buffer.
struct InputGradients {
  GradMode modeA = GradMode::Skip;
  Mat da;
  GradMode modeB = GradMode::Skip;
  Mat db;
  uint32_t firstB = 0;  // B's columns before it (a multiple of 4) are neither computed nor written
};

class DenseLayer {
 public:
  // Throws where the tuning's weight-gradient path needs what the device lacks.
  DenseLayer(Context& ctx, const core::DenseShape& shape, const MlpTuning& tuning);
  const core::DenseShape& shape() const { return shape_; }

  // y[rows][n4] = act(concat(a, b) W + bias (+ rowBias)); columns >= n are stored as 0. `b` is ignored
  // when kb == 0. rows.limited: arguments recorded for rowsPerGroup() rows per workgroup; rows.gather:
  // row i is row gather[i] of a, b, y and the row bias.
  // firstColumn (below n4, a multiple of 4; also in the two backwards): only y's columns from it on
  // are computed and stored, those before are left as they were (a layer of which a few columns are
  // read: a proposal's feature layer, whose sigma column alone is).
  void recordForward(gpu::Recorder& rec, const LayerRows& rows, const gpu::BufferRange& params, const Mat& a,
                     const Mat& b, const Mat& y, const RowBias* rowBias = nullptr, uint32_t firstColumn = 0);
  uint32_t rowsPerGroup() const { return t_.local * t_.rows; }
  // From dz = dL/d(pre-activation): grads.da and grads.db per their GradModes; StoreReluMasked
  // multiplies by [a > 0]. rows.limited: arguments recorded for dxRowsPerGroup() rows per workgroup;
  // rows past the limit are untouched. With rows.gather, a is read through it; dz, da and db stay packed.
  // firstColumn: dz's columns before it are not read, as if 0.
  void recordBackwardInput(gpu::Recorder& rec, const LayerRows& rows, const gpu::BufferRange& params, const Mat& dz,
                           const Mat& a, const InputGradients& grads, uint32_t firstColumn = 0);
  uint32_t dxRowsPerGroup() const { return t_.local * t_.dxRows; }
  // grads[W, bias] += concat(a, b)^T dz, sum(dz) (accumulates, in any order). rows.limited: only its
  // limit and base are used (the reduction is dispatched for rows.count rows, the rows at and past the
  // limit add nothing and the sweep stops there). With rows.gather, a and b are read through it.
  // firstColumn: only the gradients of the weights and biases of the columns from it on are added
  // (dz's columns before it are not read, as if 0).
  void recordBackwardWeights(gpu::Recorder& rec, const LayerRows& rows, const Mat& a, const Mat& b, const Mat& dz,
                             const gpu::BufferRange& grads, uint32_t firstColumn = 0);

 private:
  struct DwPart {
    gpu::Kernel kernel;
    uint32_t tiles;
  };
  using DwParts = std::vector<std::unique_ptr<DwPart>>;
  // The weight gradient's dispatches for the columns from firstColumn on: input A's, B's, the bias's.
  struct DwKernels {
    DwParts a, b, bias;
  };
  void addDwParts(DwParts& parts, uint32_t k4, uint64_t goff, bool ones, uint32_t firstColumn);
  // Throws unless firstColumn is a multiple of 4 below the layer's n4.
  void checkFirstColumn(uint32_t firstColumn) const;

  Context& ctx_;
  core::DenseShape shape_;
  MlpTuning t_;
  std::map<std::pair<uint32_t, uint32_t>, gpu::Kernel> forward_;  // by (ROW_BIAS_* mode, firstColumn)
  std::map<std::tuple<GradMode, GradMode, uint32_t, uint32_t>, gpu::Kernel> dx_;  // by (modeA, modeB, firstB, firstColumn)
  std::map<uint32_t, DwKernels> dw_;  // by firstColumn
};

}  // namespace vknerf::nerf

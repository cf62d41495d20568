#include "nerf/network/dense_layer.h"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "nerf/network/gradient_paths.h"
#include "vknerf/error.h"
#include "network/mlp_dense_shared.h"
#include "network/mlp_dense_dx_shared.h"
#include "network/mlp_dense_dw_shared.h"
#include "network/row_bias_shared.h"

namespace vknerf::nerf {
namespace {

using RowPush = glsl::MlpDensePush;
using DxPush = glsl::MlpDenseDxPush;
using DwPush = glsl::MlpDenseDwPush;
using RowSpec = glsl::MlpDenseSpec;
using DxSpec = glsl::MlpDenseDxSpec;
using DwSpec = glsl::MlpDenseDwSpec;

// Largest of `preferred`, 8, 4 that divides n (n is a multiple of 4).
uint32_t blockFor(uint32_t n, uint32_t preferred) {
  for (uint32_t b : {preferred, 16u, 8u, 4u})
    if (b <= preferred && b > 0 && n % b == 0) return b;
  return 4;
}

uint32_t u32(uint64_t v, const char* what) {
  if (v > UINT32_MAX) throw Error(std::string("MLP: ") + what + " does not fit 32 bits");
  return uint32_t(v);
}

}  // namespace

MlpTuning MlpTuning::forDevice(const Context& ctx) {
  MlpTuning t;
  const GradientPaths paths = gradientPathsFor(ctx);
  t.dwFloatAtomics = paths.dwFloatAtomics ? 1 : 0;
  t.dwSubgroup = paths.dwSubgroupReduce ? 1 : 0;
  if (!ctx.isCpu()) {  // a GPU: one row per lane, many lanes, shorter weight-gradient reductions
    t.local = 128;
    t.rows = 1;
    t.dxRows = 1;
    t.dwLocal = 128;
    t.dwKT = t.dwNT = 4;
    t.dwU = 4;
    t.dwRows = 64;
    t.fusedRows = 1;
  }
  // VKNERF_MLP_TUNING="rows=4,block=8,dwKT=8,..." overrides fields, for benchmarking shapes.
  if (const char* env = std::getenv("VKNERF_MLP_TUNING")) {
    std::map<std::string, uint32_t*> fields{{"local", &t.local},   {"rows", &t.rows},       {"block", &t.block},
                                            {"dxRows", &t.dxRows},
                                            {"dxBlock", &t.dxBlock}, {"dwLocal", &t.dwLocal}, {"dwKT", &t.dwKT},
                                            {"dwNT", &t.dwNT},     {"dwU", &t.dwU},         {"dwRows", &t.dwRows},
                                            {"fused", &t.fused},   {"fusedRows", &t.fusedRows},
                                            {"fusedBlock", &t.fusedBlock}, {"fusedUnroll", &t.fusedUnroll},
                                            {"dwFloatAtomics", &t.dwFloatAtomics}, {"dwSubgroup", &t.dwSubgroup}};
    std::string spec = env;
    for (size_t at = 0; at < spec.size();) {
      size_t end = std::min(spec.find(',', at), spec.size()), eq = spec.find('=', at);
      if (eq >= end) throw Error("VKNERF_MLP_TUNING: expected name=value in '" + spec + "'");
      auto it = fields.find(spec.substr(at, eq - at));
      if (it == fields.end()) throw Error("VKNERF_MLP_TUNING: unknown field '" + spec.substr(at, eq - at) + "'");
      *it->second = uint32_t(std::stoul(spec.substr(eq + 1, end - eq - 1)));
      at = end + 1;
    }
    if (t.block % 4 || t.dxBlock % 4 || t.dwKT % 4 || t.dwNT % 4 || t.fusedBlock % 4 || t.fusedBlock == 0 ||
        t.dwU == 0 || t.rows == 0 || t.dxRows == 0 || t.fusedRows == 0)
      throw Error("VKNERF_MLP_TUNING: blocks and tiles must be multiples of 4, row counts positive");
  }
  return t;
}

const gpu::ShaderCode& weightGradientShader(const MlpTuning& t) {
  if (t.dwSubgroup) return t.dwFloatAtomics ? gpu::shaders::mlp_dense_dw : gpu::shaders::mlp_dense_dw_cas;
  return t.dwFloatAtomics ? gpu::shaders::mlp_dense_dw_workgroup : gpu::shaders::mlp_dense_dw_workgroup_cas;
}

Mat Mat::rows(uint32_t first, uint32_t count) const {
  VkDeviceSize bytesPerRow = VkDeviceSize(stride) * 4;
  return {gpu::BufferRange(*range.buffer, range.offset + first * bytesPerRow, std::max<VkDeviceSize>(count, 1) * bytesPerRow),
          stride};
}

RowBias RowBias::rows(uint32_t first, uint32_t n) const {
  RowBias r = *this;
  if (rowRay) r.rowRay = gpu::rowsOf(*rowRay, 4, first, n);
  return r;
}

uint32_t rowBiasMode(const RowBias* bias) {
  if (!bias) return ROW_BIAS_NONE;
  if (bias->rowRay.has_value() != bias->rayTable.has_value())
    throw Error("MLP: a bias per row needs both the rows' rays and the rays' table rows, or neither");
  return bias->rowRay ? ROW_BIAS_PER_RAY : ROW_BIAS_ONE;
}

std::array<gpu::BufferRange, 3> rowBiasBindings(const RowBias* bias, const gpu::BufferRange& unused) {
  if (!bias) return {unused, unused, unused};  // never read (ROW_BIAS_NONE)
  return {bias->table, bias->rowRay ? *bias->rowRay : bias->table, bias->rayTable ? *bias->rayTable : bias->table};
}

DenseLayer::DenseLayer(Context& ctx, const core::DenseShape& shape, const MlpTuning& tuning)
    : ctx_(ctx), shape_(shape), t_(tuning) {
  if (shape.offset % 4) throw Error("MLP: layer weights must start on a multiple of 4 floats");
  const GradientPaths paths = gradientPathsFor(ctx);
  if (tuning.dwFloatAtomics && !paths.dwFloatAtomics)
    throw Error("MLP: the weight gradient's float atomics (shaderBufferFloat32AtomicAdd) are not on this device");
  if (tuning.dwSubgroup && !paths.dwSubgroupReduce)
    throw Error("MLP: the weight gradient's subgroupAdd (subgroup arithmetic) is not on this device");
  // The workgroup reduction's rounds fill 4096 floats of shared memory (network/mlp_dense_dw.glsl).
  if (!tuning.dwSubgroup && (tuning.dwLocal == 0 || tuning.dwLocal > 4096))
    throw Error("MLP: the weight gradient's workgroup reduction needs 1..4096 invocations a workgroup");
}

void DenseLayer::checkFirstColumn(uint32_t firstColumn) const {
  if (firstColumn % 4 || firstColumn >= shape_.n4())
    throw Error("MLP: the first output column to compute, " + std::to_string(firstColumn) +
                ", is not a multiple of 4 below " + std::to_string(shape_.n4()));
}

void DenseLayer::recordForward(gpu::Recorder& rec, const LayerRows& rows, const gpu::BufferRange& params, const Mat& a,
                               const Mat& b, const Mat& y, const RowBias* rowBias, uint32_t firstColumn) {
  const uint32_t count = rows.count;
  if (count == 0) return;
  const auto& s = shape_;
  checkFirstColumn(firstColumn);
  const uint32_t mode = rowBiasMode(rowBias);
  auto kernel = forward_.find({mode, firstColumn});
  if (kernel == forward_.end()) {
    uint32_t act = uint32_t(s.act);
    std::vector<gpu::Binding> bindings(3, gpu::Binding::TexelRgba32f);
    bindings.insert(bindings.end(), {gpu::Binding::Storage, gpu::Binding::TexelRgba32f, gpu::Binding::Storage,
                                     gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage});
    kernel = forward_.try_emplace({mode, firstColumn},
        ctx_, gpu::KernelDesc{gpu::shaders::mlp_dense, bindings,
                              sizeof(RowPush),
                              {{RowSpec::LOCAL_SIZE_X, t_.local},
                               {RowSpec::KA4, s.ka4()},
                               {RowSpec::KB4, s.kb4()},
                               {RowSpec::N4, s.n4()},
                               {RowSpec::NTRUE, s.n},
                               {RowSpec::ACT, act},
                               {RowSpec::WOFF4, u32(s.offset / 4, "weight offset")},
                               {RowSpec::R, t_.rows},
                               {RowSpec::NB, std::min(t_.block, s.n4() - firstColumn)},
                               {RowSpec::ROW_BIAS, mode},
                               {RowSpec::N_FIRST, firstColumn}}}).first;
  }
  if (rowBias) gpu::requireBytes("MLP", "the bias table", rowBias->table, uint64_t(s.n4()) * 4);
  const Mat& bb = s.kb ? b : a;
  const auto bias = rowBiasBindings(rowBias, params);
  const gpu::BufferRange* gather = rows.gather ? &*rows.gather : nullptr;
  gpu::dispatchLimited(rec, kernel->second,
                       {a.range, bb.range, params, y.range, bias[0], bias[1], bias[2], gather ? *gather : y.range},
                       RowPush{count, a.stride / 4, bb.stride / 4, y.stride / 4, 0, gather ? 1u : 0u}, rows.limited,
                       gpu::groupsFor(count, rowsPerGroup()), rows.label);
}

void DenseLayer::recordBackwardInput(gpu::Recorder& rec, const LayerRows& rows, const gpu::BufferRange& params,
                                     const Mat& dz, const Mat& a, const InputGradients& grads, uint32_t firstColumn) {
  const uint32_t count = rows.count;
  const gpu::BufferRange* gather = rows.gather ? &*rows.gather : nullptr;
  const GradMode modeA = grads.modeA;
  GradMode modeB = grads.modeB;
  const Mat &da = grads.da, &db = grads.db;
  const auto& s = shape_;
  if (s.kb == 0) modeB = GradMode::Skip;
  if (count == 0 || (modeA == GradMode::Skip && modeB == GradMode::Skip)) return;
  if (modeB == GradMode::StoreReluMasked) throw Error("MLP: input B is never ReLU-masked");
  const uint32_t firstB = modeB == GradMode::Skip ? 0 : grads.firstB;
  if (firstB % 4 || firstB > s.kb4())
    throw Error("MLP: the first B column to compute, " + std::to_string(firstB) + ", is not a multiple of 4 within " +
                std::to_string(s.kb4()));
  checkFirstColumn(firstColumn);
  auto key = std::make_tuple(modeA, modeB, firstB, firstColumn);
  auto it = dx_.find(key);
  if (it == dx_.end()) {
    gpu::KernelDesc d{gpu::shaders::mlp_dense_dx,
                      {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f,
                       gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                      sizeof(DxPush),
                      {{DxSpec::LOCAL_SIZE_X, t_.local},
                       {DxSpec::KA4, s.ka4()},
                       {DxSpec::KB4, s.kb4()},
                       {DxSpec::N4, s.n4()},
                       {DxSpec::WOFF4, u32(s.offset / 4, "weight offset")},
                       {DxSpec::R, t_.dxRows},
                       {DxSpec::KBLK, blockFor(s.ka4(), t_.dxBlock)},
                       {DxSpec::MODE_A, uint32_t(modeA)},
                       {DxSpec::MODE_B, uint32_t(modeB)},
                       {DxSpec::KB_FIRST, firstB},
                       {DxSpec::N_FIRST, firstColumn}}};
    it = dx_.emplace(key, gpu::Kernel(ctx_, std::move(d))).first;
  }
  const Mat& aa = modeA == GradMode::StoreReluMasked ? a : dz;
  const Mat& daa = modeA != GradMode::Skip ? da : db;
  const Mat& dbb = modeB != GradMode::Skip ? db : da;
  DxPush p{count, dz.stride / 4, aa.stride / 4, daa.stride / 4, dbb.stride / 4, gather ? 1u : 0u, 0};
  gpu::dispatchLimited(rec, it->second, {dz.range, aa.range, params, daa.range, dbb.range, gather ? *gather : dz.range},
                       p, rows.limited, gpu::groupsFor(count, dxRowsPerGroup()), rows.label);
}

// The columns split into a main part (tiles of NT) and a 4-wide tail, each its own pipeline.
void DenseLayer::addDwParts(DwParts& parts, uint32_t k4, uint64_t goff, bool ones, uint32_t firstColumn) {
  const auto& s = shape_;
  uint32_t kt = ones ? 1 : blockFor(k4, t_.dwKT);
  uint32_t nt = std::min(t_.dwNT, s.n4() - firstColumn);
  uint32_t nMain = firstColumn + (s.n4() - firstColumn) / nt * nt;
  auto add = [&](uint32_t n0, uint32_t nw, uint32_t ntile) {
    if (nw == 0) return;
    gpu::KernelDesc d{weightGradientShader(t_),
                      {gpu::Binding::TexelRgba32f, gpu::Binding::TexelRgba32f, gpu::Binding::Storage,
                       gpu::Binding::Storage, gpu::Binding::Storage},
                      sizeof(DwPush),
                      {{DwSpec::LOCAL_SIZE_X, t_.dwLocal},
                       {DwSpec::K4, k4},
                       {DwSpec::N4, s.n4()},
                       {DwSpec::N0, n0},
                       {DwSpec::NW, nw},
                       {DwSpec::KT, kt},
                       {DwSpec::NT, ntile},
                       {DwSpec::U, t_.dwU},
                       {DwSpec::GOFF, u32(goff, "gradient offset")},
                       {DwSpec::ONES, ones ? 1u : 0u}}};
    parts.push_back(std::make_unique<DwPart>(DwPart{gpu::Kernel(ctx_, std::move(d)), (k4 / kt) * (nw / ntile)}));
  };
  add(firstColumn, nMain - firstColumn, nt);
  add(nMain, s.n4() - nMain, 4);
}

void DenseLayer::recordBackwardWeights(gpu::Recorder& rec, const LayerRows& rows, const Mat& a, const Mat& b,
                                       const Mat& dz, const gpu::BufferRange& grads, uint32_t firstColumn) {
  const uint32_t count = rows.count;
  const gpu::LimitedRows& limited = rows.limited;
  const gpu::BufferRange* gather = rows.gather ? &*rows.gather : nullptr;
  if (count == 0) return;
  const auto& s = shape_;
  checkFirstColumn(firstColumn);
  DwKernels& dw = dw_[firstColumn];
  if (dw.a.empty()) {
    addDwParts(dw.a, s.ka4(), s.offset, false, firstColumn);
    if (s.kb) addDwParts(dw.b, s.kb4(), s.offset + uint64_t(s.ka4()) * s.n4(), false, firstColumn);
    addDwParts(dw.bias, 1, s.biasOffset(), true, firstColumn);
  }
  // Each invocation sums dwRows rows (iters * U); enough workgroups to cover the batch.
  uint32_t iters = std::max(1u, t_.dwRows / t_.dwU);
  uint32_t groups = gpu::groupsFor(count, uint64_t(t_.dwLocal) * t_.dwU * iters);
  iters = gpu::groupsFor(count, uint64_t(groups) * t_.dwLocal * t_.dwU);  // rebalance the last partial sweep
  auto run = [&](DwParts& parts, const Mat& x) {
    for (auto& part : parts) {
      DwPush p{count, x.stride / 4, dz.stride / 4, iters, gather ? 1u : 0u, limited.base};
      rec.dispatch(part->kernel, {x.range, dz.range, grads, gather ? *gather : dz.range, limited.limit}, p, groups,
                   part->tiles, 1, rows.label);
    }
  };
  run(dw.a, a);
  if (s.kb) run(dw.b, b);
  run(dw.bias, dz);
}

}  // namespace vknerf::nerf

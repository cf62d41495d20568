// The MLP kernels (mlp_*.comp through nerf/network/mlp.h) against the CPU reference (tests/reference/network/mlp.h).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "nerf/network/mlp.h"
#include "reference/encoding/appearance.h"
#include "reference/network/mlp.h"
#include "reference/rng.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

// Rows of `dims` values in [-scale, scale] at `stride` floats per row, padding columns zero.
std::vector<float> features(uint32_t rows, uint32_t dims, uint32_t stride, uint32_t seed, float scale = 1.0f) {
  std::vector<float> v(size_t(rows) * stride, 0.0f);
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t k = 0; k < dims; ++k) v[size_t(r) * stride + k] = scale * (2.0f * ref::rng01(seed, r, k) - 1.0f);
  return v;
}

// Forward tolerance. Each output is a chain of <= 6 layers of dot products of length K <= 128 in
// float; Higham's bound for one is K*u*sum|x_k w_k| ~ 128 * 6e-8 ~ 8e-6 relative to the sum of
// magnitudes, which for these O(1) inputs and PyTorch-scaled weights is a few times the result.
// Over the chain: ~5e-5; the reference runs in double.
constexpr double kFwdRel = 2e-4, kFwdAbs = 2e-5;
// Gradient tolerance. An entry of dW sums B ~ 300 per-sample products (in an order the path and the
// atomics choose), each after a backward chain like the forward one; the float error is
// ~(B + 6K) u sum|terms| for any order of the sum, so one tolerance holds for every weight-gradient
// path. With cancellation between samples the sum of magnitudes can exceed the entry, so the
// absolute part scales with the largest gradient of the buffer: 1e-4 * max|g|, 1e-3 relative.
constexpr double kGradRel = 1e-3, kGradAbsScale = 1e-4;

struct NerfRun {
  std::vector<float> out, grads, dPos, dDir;
};

struct NerfCase {
  nerf::MlpConfig cfg;
  uint32_t count = 0;
  float inputScale = 1.0f, paramScale = 1.0f;
  uint32_t chunkRows = 0;  // 0: device default
  bool backward = true;
  uint32_t dDirFirst = 0;  // dDir's columns before it are not to be written
  bool densityOnly = false;  // NerfRows::densityOnly: trained on sigma alone (dOut's rgb taken as 0)
};

constexpr float kUnwritten = -7.0f;  // what the kernels find in their outputs, where nothing is to be written

struct NerfData {
  std::vector<float> params, pos, dir, dOut;
};

NerfData makeData(const nerf::NerfMlp& mlp, const NerfCase& c) {
  NerfData d;
  d.params = mlp.initialParameters();
  for (auto& v : d.params) v *= c.paramScale;
  d.pos = features(c.count, c.cfg.posDims, mlp.posStride(), 100, c.inputScale);
  d.dir = features(c.count, c.cfg.dirDims, mlp.dirStride(), 200, c.inputScale);
  d.dOut = features(c.count, 4, 4, 300);
  return d;
}

NerfRun runNerf(Context& ctx, nerf::NerfMlp& mlp, const NerfCase& c, const NerfData& d) {
  auto params = gpu::Buffer::of(ctx, d.params);
  auto pos = gpu::Buffer::of(ctx, d.pos.empty() ? std::vector<float>(4) : d.pos);
  auto dir = gpu::Buffer::of(ctx, d.dir.empty() ? std::vector<float>(4) : d.dir);
  auto dOut = gpu::Buffer::of(ctx, d.dOut.empty() ? std::vector<float>(4) : d.dOut);
  size_t outFloats = std::max<size_t>(size_t(c.count) * 4, 4);
  gpu::Buffer out(ctx, outFloats * 4), grads(ctx, d.params.size() * 4), dPos(ctx, std::max<size_t>(d.pos.size(), 4) * 4);
  auto dDir = gpu::Buffer::of(ctx, std::vector<float>(std::max<size_t>(d.dir.size(), 4), kUnwritten));
  std::vector<float> sentinel(outFloats, kUnwritten);
  out.upload(sentinel);
  grads.zero();
  nerf::NerfMlp::Workspace ws(ctx, mlp, c.count);
  if (c.densityOnly) {
    // The whole network's step first, on the same workspace: its colour activations and gradients
    // are left there (not zero), so a density-only pass that read them would show it.
    auto finite = gpu::Buffer::of(ctx, features(c.count, 4, 4, 400));
    auto dirs = gpu::Buffer::of(ctx, features(c.count, c.cfg.dirDims, mlp.dirStride(), 500));
    gpu::Buffer scratch(ctx, d.params.size() * 4);
    scratch.zero();
    test::submitOnce(ctx, [&](gpu::Recorder& rec) {
      const nerf::NerfRows rows{c.count, pos, dirs, out};
      mlp.recordForward(rec, rows, params, &ws);
      mlp.recordBackward(rec, rows, params, {finite, scratch}, ws);
    });
    out.upload(std::vector<float>(outFloats, kUnwritten));
  }
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    nerf::NerfRows rows{c.count, pos, dir, out};
    rows.densityOnly = c.densityOnly;
    mlp.recordForward(rec, rows, params, &ws);
    nerf::NerfGradients gradients{dOut, grads, gpu::BufferRange(dPos)};
    if (!c.densityOnly) gradients.dDir = gpu::BufferRange(dDir), gradients.dDirFirst = c.dDirFirst;
    if (c.backward) mlp.recordBackward(rec, rows, params, gradients, ws);
  });
  return {out.download<float>(outFloats), grads.download<float>(d.params.size()), dPos.download<float>(d.pos.size()),
          dDir.download<float>(d.dir.size())};
}

// The forward alone, without a workspace (nothing kept for backward).
std::vector<float> inferNerf(Context& ctx, nerf::NerfMlp& mlp, uint32_t count, const NerfData& d) {
  auto params = gpu::Buffer::of(ctx, d.params);
  auto pos = gpu::Buffer::of(ctx, d.pos), dir = gpu::Buffer::of(ctx, d.dir);
  gpu::Buffer out(ctx, size_t(count) * 16);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) { mlp.recordForward(rec, {count, pos, dir, out}, params, nullptr); });
  return out.download<float>(size_t(count) * 4);
}

struct NerfRef {
  std::vector<double> out, grads, dPos, dDir;
};

NerfRef referenceNerf(const nerf::NerfMlp& mlp, const NerfCase& c, const NerfData& d) {
  const auto& s = mlp.shape();
  NerfRef r{std::vector<double>(size_t(c.count) * 4), std::vector<double>(s.total, 0.0),
            std::vector<double>(d.pos.size(), 0.0), std::vector<double>(d.dir.size(), 0.0)};
  std::vector<double> pos(s.posDims), dir(s.dirDims);
  for (uint32_t i = 0; i < c.count; ++i) {
    for (uint32_t k = 0; k < s.posDims; ++k) pos[k] = d.pos[size_t(i) * mlp.posStride() + k];
    for (uint32_t k = 0; k < s.dirDims; ++k) dir[k] = d.dir[size_t(i) * mlp.dirStride() + k];
    auto fw = ref::nerfForward<double>(s, d.params, pos.data(), dir.data());
    for (int k = 0; k < 4; ++k) r.out[4 * i + k] = fw.out[k];
    if (!c.backward) continue;
    std::array<double, 4> g{d.dOut[4 * i], d.dOut[4 * i + 1], d.dOut[4 * i + 2], d.dOut[4 * i + 3]};
    if (c.densityOnly) g[0] = g[1] = g[2] = 0.0;
    ref::nerfBackward(s, d.params, pos.data(), dir.data(), fw, g, r.grads, &r.dPos[size_t(i) * mlp.posStride()],
                      &r.dDir[size_t(i) * mlp.dirStride()]);
  }
  return r;
}

void expectNear(const std::vector<float>& gpu, const std::vector<double>& ref, double rel, double abs, const char* what) {
  ASSERT_EQ(gpu.size(), ref.size());
  int failures = 0;
  for (size_t i = 0; i < gpu.size() && failures < 10; ++i) {
    auto ok = test::near(gpu[i], ref[i], rel, abs);
    if (!ok) ++failures;
    EXPECT_TRUE(ok) << what << " [" << i << "]";
  }
}

double maxAbs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

void checkNerf(Context& ctx, const NerfCase& c, const nerf::MlpTuning& tuning) {
  nerf::NerfMlp mlp(ctx, c.cfg, tuning);
  if (c.chunkRows) mlp.setChunkRows(c.chunkRows);
  auto data = makeData(mlp, c);
  auto gpu = runNerf(ctx, mlp, c, data);
  auto ref = referenceNerf(mlp, c, data);
  expectNear(gpu.out, ref.out, kFwdRel, kFwdAbs, "out");
  if (!c.backward) return;
  double gScale = maxAbs(ref.grads);
  ASSERT_GT(gScale, 0.0);
  expectNear(gpu.grads, ref.grads, kGradRel, kGradAbsScale * gScale, "grads");
  // dPos is per sample (no sum over the batch): the forward-style tolerance, scaled to its magnitude.
  expectNear(gpu.dPos, ref.dPos, kGradRel, kGradAbsScale * maxAbs(ref.dPos), "dPos");
  // dDir (what an appearance vector beside the direction trains from) is per sample too, through
  // the head and the colour layer only: the same tolerance. Its padding columns are written 0; the
  // columns before dDirFirst are left as they were.
  ASSERT_GT(maxAbs(ref.dDir), 0.0);
  const double dDirAbs = kGradAbsScale * maxAbs(ref.dDir);
  for (size_t i = 0; i < ref.dDir.size(); ++i)
    if (i % mlp.dirStride() < c.dDirFirst) ref.dDir[i] = kUnwritten;
  expectNear(gpu.dDir, ref.dDir, kGradRel, dDirAbs, "dDir");
}

void checkNerf(Context& ctx, const NerfCase& c) { checkNerf(ctx, c, nerf::MlpTuning::forDevice(ctx)); }

nerf::MlpConfig smallNerf(DensityActivation density = DensityActivation::Relu) {
  nerf::MlpConfig c;
  c.depth = 4;
  c.width = 32;
  c.skipLayer = 2;
  c.density = density;
  c.seed = 9;
  return c;
}

class MlpNerf : public test::GpuTest {};
class MlpDense : public test::GpuTest {};

// The weight gradient's paths (nerf/network/gradient_paths.h): float atomicAdd or compare-and-swap
// adds, after subgroupAdd or a workgroup reduction in shared memory. lavapipe has every feature,
// so every path runs here; each must match the reference as the device's default does.
struct DwPath {
  uint32_t floatAtomics, subgroup;
};
class MlpPaths : public test::GpuTest, public testing::WithParamInterface<DwPath> {
 protected:
  void SetUp() override {
    test::GpuTest::SetUp();
    if (!test::deviceRuns(GetParam().floatAtomics, GetParam().subgroup))
      GTEST_SKIP() << "this device (its profile) lacks the path's float atomics or subgroup arithmetic";
  }
  nerf::MlpTuning tuning() {
    nerf::MlpTuning t = nerf::MlpTuning::forDevice(ctx());
    t.dwFloatAtomics = GetParam().floatAtomics, t.dwSubgroup = GetParam().subgroup;
    return t;
  }
};
std::string dwPathName(const testing::TestParamInfo<DwPath>& info) {
  return std::string(info.param.floatAtomics ? "FloatAtomic" : "CompareSwap") +
         (info.param.subgroup ? "AfterSubgroupAdd" : "AfterWorkgroupReduce");
}
class MlpNerfPaths : public MlpPaths {};
class MlpDensePaths : public MlpPaths {};

}  // namespace

// 300 rows: not a multiple of any workgroup size, exercising the clamped tail rows.
TEST_P(MlpNerfPaths, ForwardAndBackwardMatchReference) { checkNerf(ctx(), {smallNerf(), 300}, tuning()); }

// The direction input's gradient from a column on (an appearance vector's, after SH(d)'s).
TEST_F(MlpNerf, DirectionGradientFromAColumnOn) {
  NerfCase c{smallNerf(), 200};
  c.cfg.dirDims = 12;
  c.dDirFirst = 4;
  checkNerf(ctx(), c);
}

TEST_F(MlpNerf, TruncExpAndSoftplusDensities) {
  checkNerf(ctx(), {smallNerf(DensityActivation::TruncExp), 70});
  checkNerf(ctx(), {smallNerf(DensityActivation::Softplus), 70});
}

TEST_P(MlpNerfPaths, NoSkipLayerAndSingleRow) {
  auto cfg = smallNerf();
  cfg.skipLayer = 0;
  cfg.depth = 2;
  checkNerf(ctx(), {cfg, 1}, tuning());
}

// A feature narrower than the trunk: the fast model's (64 wide, 16 features + the density) and
// one whose feature + density columns (13) fill an exact 16-column block.
TEST_P(MlpNerfPaths, NarrowFeatureMatchesReference) {
  auto cfg = smallNerf(DensityActivation::TruncExp);
  cfg.featureWidth = 12;
  checkNerf(ctx(), {cfg, 131}, tuning());
  cfg.depth = 1, cfg.skipLayer = 0, cfg.width = 64, cfg.posDims = 16, cfg.dirDims = 16, cfg.featureWidth = 16;
  checkNerf(ctx(), {cfg, 200}, tuning());
}

TEST_P(MlpNerfPaths, ChunkedBatchMatchesReference) {
  // 64-row chunks: 4 chunks, the last one partial; bindings at row offsets, gradients accumulated.
  checkNerf(ctx(), {smallNerf(), 229, 1.0f, 1.0f, 64}, tuning());
}

// A GPU's weight-gradient shape (MlpTuning::forDevice off the CPU: 128 invocations a workgroup,
// 4 x 4 tiles, 4 rows an iteration), one iteration an invocation so that 1500 rows span three
// workgroups along the rows: they add into every entry concurrently (the compare-and-swap loop's
// retries), and the workgroup reduction's one round holds the whole tile. 1500 rows in the error
// bound above: ~(1500 + 6K) u ~ 1.3e-4 of the sum of magnitudes, within the same tolerance.
TEST_P(MlpNerfPaths, GpuWeightGradientShapeMatchesReference) {
  nerf::MlpTuning t = tuning();
  t.dwLocal = 128, t.dwKT = t.dwNT = 4, t.dwU = 4, t.dwRows = 4;
  checkNerf(ctx(), {smallNerf(), 1500}, t);
}

// A device without float atomics (the same device adopted as if the caller had not enabled
// shaderBufferFloat32AtomicAdd) trains: its tuning adds by compare-and-swap, and the gradients match
// the reference with the same tolerance.
TEST_F(MlpNerf, DeviceWithoutFloatAtomicsAddsByCompareAndSwap) {
  auto adopted = Context::adopt({ctx().instance(), ctx().physicalDevice(), ctx().device(), ctx().queueFamily(),
                                 ctx().queue(), false});
  ASSERT_FALSE(adopted->floatAtomics());
  const nerf::MlpTuning t = nerf::MlpTuning::forDevice(*adopted);
  EXPECT_EQ(t.dwFloatAtomics, 0u);
  checkNerf(*adopted, {smallNerf(), 300}, t);
  nerf::MlpTuning atomic = t;
  atomic.dwFloatAtomics = 1;
  EXPECT_THROW(nerf::NerfMlp(*adopted, smallNerf(), atomic), Error);
}

TEST_F(MlpNerf, EmptyBatchDispatchesNothing) {
  nerf::NerfMlp mlp(ctx(), smallNerf());
  NerfCase c{smallNerf(), 0};
  auto gpu = runNerf(ctx(), mlp, c, makeData(mlp, c));
  for (float v : gpu.out) EXPECT_EQ(v, -7.0f);  // the sentinel is untouched
  for (float g : gpu.grads) EXPECT_EQ(g, 0.0f);
}

TEST_F(MlpNerf, SigmaIgnoresDirection) {
  nerf::MlpConfig cfg = smallNerf(DensityActivation::Softplus);
  nerf::NerfMlp mlp(ctx(), cfg);
  NerfCase c{cfg, 64};
  auto a = makeData(mlp, c), b = a;
  // The same positions with other directions: sigma must be bit-identical, rgb must move.
  b.dir = features(c.count, cfg.dirDims, mlp.dirStride(), 999);
  c.backward = false;
  auto ga = runNerf(ctx(), mlp, c, a), gb = runNerf(ctx(), mlp, c, b);
  int rgbMoved = 0;
  for (uint32_t i = 0; i < c.count; ++i) {
    EXPECT_EQ(ga.out[4 * i + 3], gb.out[4 * i + 3]);
    rgbMoved += ga.out[4 * i] != gb.out[4 * i];
  }
  EXPECT_GT(rgbMoved, int(c.count) / 2);
}

TEST_F(MlpNerf, LargePreactivationsStayFinite) {
  // Inputs x100 and weights x30: pre-activations reach ~1e6 and beyond; sigmoid and the density
  // activations saturate, nothing may become Inf or NaN, and the reference still agrees.
  for (auto density : {DensityActivation::Relu, DensityActivation::TruncExp, DensityActivation::Softplus}) {
    NerfCase c{smallNerf(density), 96, 100.0f, 30.0f};
    nerf::NerfMlp mlp(ctx(), c.cfg);
    auto data = makeData(mlp, c);
    auto gpu = runNerf(ctx(), mlp, c, data);
    auto ref = referenceNerf(mlp, c, data);
    for (float v : gpu.out) ASSERT_TRUE(std::isfinite(v));
    for (float v : gpu.grads) ASSERT_TRUE(std::isfinite(v));
    for (float v : gpu.dPos) ASSERT_TRUE(std::isfinite(v));
    double preScale = 0;
    for (size_t i = 0; i < ref.out.size(); i += 4) preScale = std::max(preScale, ref.out[i + 3]);
    EXPECT_GT(preScale, 1e3);  // the case is really extreme
    // Relative agreement survives (the absolute parts scale with the outputs/gradients).
    for (size_t i = 0; i < ref.out.size(); ++i)
      EXPECT_TRUE(test::near(gpu.out[i], ref.out[i], 1e-3, 1e-3 * (i % 4 == 3 ? preScale : 1.0))) << i;
    double gScale = maxAbs(ref.grads);
    int bad = 0;
    for (size_t i = 0; i < ref.grads.size(); ++i) bad += !test::near(gpu.grads[i], ref.grads[i], 1e-2, 1e-3 * gScale);
    EXPECT_EQ(bad, 0);
  }
}

TEST_F(MlpNerf, BatchLargerThanOneBinding) {
  // gamma(x) for 530,000 rows at 64 floats is 136 MB, over the 128 MiB maxStorageBufferRange: the
  // MLP must split the batch. A narrow network keeps it quick; rows near the chunk boundary and a
  // spread of others are checked against the reference, and the gradient sums all rows.
  nerf::MlpConfig cfg;
  cfg.depth = 1;
  cfg.width = 8;
  cfg.skipLayer = 0;
  cfg.seed = 4;
  nerf::NerfMlp mlp(ctx(), cfg);
  const uint32_t count = 530000;
  ASSERT_GT(uint64_t(count) * mlp.posStride() * 4, ctx().properties().limits.maxStorageBufferRange);
  ASSERT_LT(mlp.chunkRows(), count);
  NerfCase c{cfg, count};
  auto data = makeData(mlp, c);
  auto gpu = runNerf(ctx(), mlp, c, data);

  const auto& s = mlp.shape();
  std::vector<double> grads(s.total, 0.0), pos(s.posDims), dir(s.dirDims);
  std::vector<uint32_t> checkRows;
  for (uint32_t i = 0; i < count; ++i) {
    for (uint32_t k = 0; k < s.posDims; ++k) pos[k] = data.pos[size_t(i) * mlp.posStride() + k];
    for (uint32_t k = 0; k < s.dirDims; ++k) dir[k] = data.dir[size_t(i) * mlp.dirStride() + k];
    auto fw = ref::nerfForward<double>(s, data.params, pos.data(), dir.data());
    bool boundary = i % mlp.chunkRows() < 2 || i % mlp.chunkRows() >= mlp.chunkRows() - 2 || i + 1 == count;
    if (boundary || i % 4099 == 0)
      for (int k = 0; k < 4; ++k) ASSERT_TRUE(test::near(gpu.out[4 * size_t(i) + k], fw.out[k], kFwdRel, kFwdAbs)) << i;
    std::array<double, 4> g{data.dOut[4 * size_t(i)], data.dOut[4 * size_t(i) + 1], data.dOut[4 * size_t(i) + 2],
                            data.dOut[4 * size_t(i) + 3]};
    ref::nerfBackward(s, data.params, pos.data(), dir.data(), fw, g, grads, (double*)nullptr, (double*)nullptr);
  }
  // 530k-term sums in float atomics: error ~ sqrt(B) u to B u relative to the sum of magnitudes.
  double gScale = maxAbs(grads);
  expectNear(gpu.grads, grads, 1e-2, 2e-3 * gScale, "grads");
}

TEST_F(MlpNerf, InferenceWithoutWorkspaceMatchesTraining) {
  auto cfg = smallNerf();
  nerf::NerfMlp mlp(ctx(), cfg);
  mlp.setChunkRows(64);  // the internal scratch then serves 64 rows at a time
  NerfCase c{cfg, 150};
  auto data = makeData(mlp, c);
  auto ref = referenceNerf(mlp, {cfg, c.count, 1.0f, 1.0f, 0, false}, data);
  expectNear(inferNerf(ctx(), mlp, c.count, data), ref.out, kFwdRel, kFwdAbs, "out");
}

// The density alone (mlp_nerf_density.comp after the trunk): against the reference's sigma with the
// forward tolerance, and against the full forward's sigma to the rounding of one operation (the same
// sums in another kernel: the driver may contract a multiply-add in one and not the other, as in
// FusedForwardMatchesTheLayeredOne). Shapes: a skip connection and softplus density over 64-row
// chunks (3 chunks, the last partial); the fast model's narrow feature with truncated exp; two trunk
// layers and a full-width feature, truncated exp. (ReLU would leave these initial fields at 0.)
// The floats past the batch keep their sentinel.
TEST_F(MlpNerf, DensityAloneMatchesTheForward) {
  struct Case {
    nerf::MlpConfig cfg;
    uint32_t chunkRows;
  };
  nerf::MlpConfig fast;
  fast.depth = 1, fast.width = 64, fast.skipLayer = 0, fast.posDims = 16, fast.dirDims = 16, fast.featureWidth = 16;
  fast.density = DensityActivation::TruncExp, fast.seed = 5;
  nerf::MlpConfig wide = smallNerf(DensityActivation::TruncExp);
  wide.skipLayer = 0, wide.depth = 2;
  const Case cases[] = {{smallNerf(DensityActivation::Softplus), 64}, {fast, 0}, {wide, 0}};
  for (const Case& k : cases) {
    SCOPED_TRACE(testing::Message() << "depth " << k.cfg.depth << ", width " << k.cfg.width << ", feature "
                                    << k.cfg.featureWidth << ", skip " << k.cfg.skipLayer);
    nerf::NerfMlp mlp(ctx(), k.cfg);
    if (k.chunkRows) mlp.setChunkRows(k.chunkRows);
    NerfCase c{k.cfg, 150, 1.0f, 1.0f, 0, false};
    const auto data = makeData(mlp, c);
    auto params = gpu::Buffer::of(ctx(), data.params);
    auto pos = gpu::Buffer::of(ctx(), data.pos);
    auto density = gpu::Buffer::of(ctx(), std::vector<float>(c.count + 5, -7.0f));
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) { mlp.recordDensity(rec, c.count, params, pos, density); });
    const auto got = density.download<float>(c.count + 5);
    const auto ref = referenceNerf(mlp, c, data);
    const auto full = inferNerf(ctx(), mlp, c.count, data);
    std::vector<double> refSigma(c.count), fullSigma(c.count);
    for (uint32_t i = 0; i < c.count; ++i) refSigma[i] = ref.out[4 * i + 3], fullSigma[i] = full[4 * i + 3];
    const std::vector<float> gotSigma(got.begin(), got.begin() + c.count);
    expectNear(gotSigma, refSigma, kFwdRel, kFwdAbs, "density against the reference");
    constexpr double kRounding = 1e-6;
    expectNear(gotSigma, fullSigma, kRounding, kRounding * maxAbs(fullSigma), "density against the full forward");
    EXPECT_GT(maxAbs(refSigma), 0.0);  // not a field of zeros
    for (uint32_t i = c.count; i < c.count + 5; ++i) EXPECT_EQ(got[i], -7.0f) << i;
  }
}

// The shapes a density-only pass is for: the fast model's network (64 wide, a 16-wide feature) and
// the proposal's (16 wide, the whole layer its feature, one direction coefficient).
static std::vector<nerf::MlpConfig> densityOnlyShapes(uint32_t seed) {
  nerf::MlpConfig fast;
  fast.depth = 1, fast.width = 64, fast.skipLayer = 0, fast.posDims = 16, fast.dirDims = 16, fast.featureWidth = 16;
  fast.density = DensityActivation::TruncExp, fast.seed = seed;
  nerf::MlpConfig proposal = fast;
  proposal.width = 16, proposal.posDims = 10, proposal.dirDims = 1, proposal.featureWidth = 0;
  return {fast, proposal};
}

// A forward that reads the density alone (NerfRows::densityOnly, the proposal's at render time):
// the fused kernel computes the trunk and sigma's column only, so its density is the full fused
// forward's to the rounding of one operation (the same sums, another specialization; as in
// FusedForwardMatchesTheLayeredOne) and against the reference within the forward tolerance; its
// rgb is exactly 0, and it reads neither the direction (NaN there changes nothing) nor the colour
// bias. Rows past the batch keep their sentinel. Shapes: the fast model's (64 wide, a 16-wide
// feature) and the proposal's (16 wide, the whole layer as its feature, one direction coefficient),
// under the device's tuning (fused on lavapipe) and with the fused kernel off, where the layered
// forward skips the colour layer and writes the density from the feature layer's sigma column.
TEST_F(MlpNerf, DensityOnlyForwardMatchesTheFullOne) {
  for (const nerf::MlpConfig& cfg : densityOnlyShapes(9))
    for (const bool fusedOn : {true, false}) {
      SCOPED_TRACE(testing::Message() << "width " << cfg.width << (fusedOn ? ", fused" : ", layered"));
      auto tuning = nerf::MlpTuning::forDevice(ctx());
      if (fusedOn) {
        tuning.fused = 3, tuning.fusedUnroll = 0;  // the block loop (the unrolled variant compiles for ~45 s)
      } else {
        tuning.fused = 0;
      }
      nerf::NerfMlp mlp(ctx(), cfg, tuning);
      ASSERT_EQ(mlp.fusedForward(false), fusedOn);
      mlp.setChunkRows(128);
      NerfCase c{cfg, 301, 1.0f, 1.0f, 0, false};
      const NerfData data = makeData(mlp, c);
      const std::vector<float> full = inferNerf(ctx(), mlp, c.count, data);
      NerfData noDirection = data;
      std::fill(noDirection.dir.begin(), noDirection.dir.end(), std::nanf(""));
      auto params = gpu::Buffer::of(ctx(), noDirection.params);
      auto pos = gpu::Buffer::of(ctx(), noDirection.pos), dir = gpu::Buffer::of(ctx(), noDirection.dir);
      auto out = gpu::Buffer::of(ctx(), std::vector<float>(size_t(c.count + 2) * 4, -7.0f));
      auto bias = gpu::Buffer::of(ctx(), std::vector<float>(cfg.width / 2, std::nanf("")));  // every row's
      nerf::NerfRows rows{c.count, pos, dir, out};
      rows.densityOnly = true;
      rows.colourBias = nerf::RowBias{bias};
      test::submitOnce(ctx(), [&](gpu::Recorder& rec) { mlp.recordForward(rec, rows, params, nullptr); });
      const std::vector<float> got = out.download<float>(size_t(c.count + 2) * 4);
      const NerfRef ref = referenceNerf(mlp, c, data);
      std::vector<float> gotSigma(c.count);
      std::vector<double> refSigma(c.count), fullSigma(c.count);
      for (uint32_t i = 0; i < c.count; ++i)
        gotSigma[i] = got[4 * i + 3], refSigma[i] = ref.out[4 * i + 3], fullSigma[i] = full[4 * i + 3];
      constexpr double kRounding = 1e-6;
      expectNear(gotSigma, fullSigma, kRounding, kRounding * maxAbs(fullSigma), "density against the full forward");
      expectNear(gotSigma, refSigma, kFwdRel, kFwdAbs, "density against the reference");
      EXPECT_GT(maxAbs(refSigma), 0.0);  // not a field of zeros
      for (uint32_t i = 0; i < c.count; ++i)
        for (int k = 0; k < 3; ++k) ASSERT_EQ(got[4 * i + k], 0.0f) << "row " << i << ", channel " << k;
      for (size_t i = size_t(c.count) * 4; i < got.size(); ++i) EXPECT_EQ(got[i], -7.0f) << i;
    }
}

// Training on the density alone (NerfRows::densityOnly in the forward with kept activations and in
// the backward: the proposal's, whose loss reads its sigma only): against the reference's forward
// and its backward from dL/d(r, g, b, sigma) = (0, 0, 0, dSigma), the forward and gradient
// tolerances above (the same sums as the whole network's, which FusedForwardMatchesTheLayeredOne and
// ForwardAndBackwardMatchReference hold to them). dOut's rgb is NaN (never read); out's rgb is
// exactly 0; the colour layer's and the head's gradients stay exactly 0 (not written: the buffer
// starts zeroed); dPos holds the gradient through sigma. Shapes: the fast model's (a 16-wide
// feature of 64) and the proposal's (16 wide, the whole layer its feature), over 128-row chunks.
TEST_F(MlpNerf, DensityOnlyTrainingMatchesTheReferenceOnASigmaGradient) {
  for (const nerf::MlpConfig& cfg : densityOnlyShapes(5)) {
    SCOPED_TRACE(testing::Message() << "width " << cfg.width);
    nerf::NerfMlp mlp(ctx(), cfg);
    mlp.setChunkRows(128);
    NerfCase c{cfg, 301, 1.0f, 1.0f, 128};
    c.densityOnly = true;
    const NerfData data = makeData(mlp, c);
    NerfData unread = data;
    for (uint32_t i = 0; i < c.count; ++i)
      for (int k = 0; k < 3; ++k) unread.dOut[4 * i + k] = std::nanf("");
    std::fill(unread.dir.begin(), unread.dir.end(), std::nanf(""));
    const NerfRun got = runNerf(ctx(), mlp, c, unread);
    const NerfRef ref = referenceNerf(mlp, c, data);

    std::vector<float> gotSigma(c.count);
    std::vector<double> refSigma(c.count);
    for (uint32_t i = 0; i < c.count; ++i) {
      gotSigma[i] = got.out[4 * i + 3], refSigma[i] = ref.out[4 * i + 3];
      for (int k = 0; k < 3; ++k) ASSERT_EQ(got.out[4 * i + k], 0.0f) << "row " << i << ", channel " << k;
    }
    expectNear(gotSigma, refSigma, kFwdRel, kFwdAbs, "sigma");
    expectNear(got.grads, ref.grads, kGradRel, kGradAbsScale * maxAbs(ref.grads), "grads");
    expectNear(got.dPos, ref.dPos, kGradRel, kGradAbsScale * maxAbs(ref.dPos), "dPos");
    const core::NerfShape& s = mlp.shape();
    const size_t colourFirst = s.colour().offset, colourEnd = s.head().offset + s.head().floats();
    ASSERT_LT(colourFirst, colourEnd);
    for (size_t i = colourFirst; i < colourEnd; ++i) ASSERT_EQ(got.grads[i], 0.0f) << "colour/head parameter " << i;
    EXPECT_GT(maxAbs(ref.grads), 0.0);  // sigma's gradient reaches the trunk and the feature layer
    EXPECT_GT(maxAbs(ref.dPos), 0.0);
  }
}

// The fused forward (mlp_nerf_fused.comp) sums each layer in the layered kernels' order
// (network/dense_block.glsl), so it agrees with the layered path to the rounding of a single
// operation: the driver may contract a multiply and an add into one fused multiply-add in one
// kernel and not in the other (seen: 1 ulp, with a fused backward). The outputs, and dPos,
// which is per sample and reads every activation the forward kept (the ReLU masks, the feature,
// the colour layer), are held to 1e-6 relative (8 ulps) plus 1e-6 of the largest value; the weight
// gradients sum with float atomics in any order and get the reference tolerance. Cases, over
// 128-row chunks: the fast model's shape with the CPU's tuning (8 rows an invocation) and a GPU's
// (1); two trunk layers with padded inputs and 3 rows an invocation (not a divisor of the
// workgroup's); a width of 8; 26 inputs (13 hash levels) at 8 rows, fused in the block loop alone.
TEST_F(MlpNerf, FusedForwardMatchesTheLayeredOne) {
  struct Case {
    uint32_t depth, width, posDims, dirDims, featureWidth;
    DensityActivation density;
    uint32_t rows, block;
  };
  const Case cases[] = {{1, 64, 16, 16, 16, DensityActivation::TruncExp, 8, 4},
                        {1, 64, 16, 16, 16, DensityActivation::TruncExp, 1, 8},
                        // 13 hash levels (fruit's 6 cascades): unrolled past the compile bound, fused in the block loop
                        {1, 64, 26, 16, 16, DensityActivation::TruncExp, 8, 4},
                        {2, 32, 21, 9, 8, DensityActivation::Softplus, 3, 4},
                        {1, 8, 5, 3, 0, DensityActivation::Relu, 8, 4}};
  for (const Case& k : cases) {
    SCOPED_TRACE(testing::Message() << "depth " << k.depth << ", width " << k.width << ", " << k.rows << " rows an invocation");
    nerf::MlpConfig cfg;
    cfg.depth = k.depth, cfg.width = k.width, cfg.skipLayer = 0, cfg.posDims = k.posDims, cfg.dirDims = k.dirDims;
    cfg.featureWidth = k.featureWidth, cfg.density = k.density, cfg.seed = 21;
    auto tuning = nerf::MlpTuning::forDevice(ctx());
    tuning.fused = 0;
    nerf::NerfMlp layered(ctx(), cfg, tuning);
    tuning.fused = 3, tuning.fusedRows = k.rows, tuning.fusedBlock = k.block;
    // Unrolled output blocks only in the narrowest case: the fast model's shape unrolled takes
    // ~45 s to compile on lavapipe, and the block loop and its unrolling are the same source.
    tuning.fusedUnroll = k.width <= 8 ? 3 : 0;
    nerf::NerfMlp fused(ctx(), cfg, tuning);
    ASSERT_FALSE(layered.fusedForward(true) || layered.fusedForward(false));
    ASSERT_TRUE(fused.fusedForward(true) && fused.fusedForward(false));
    layered.setChunkRows(128);
    fused.setChunkRows(128);
    NerfCase c{cfg, 301};
    const auto data = makeData(layered, c);
    const auto want = runNerf(ctx(), layered, c, data), got = runNerf(ctx(), fused, c, data);
    auto asDouble = [](const std::vector<float>& v) { return std::vector<double>(v.begin(), v.end()); };
    auto maxOf = [&](const std::vector<float>& v) { return maxAbs(asDouble(v)); };
    constexpr double kRounding = 1e-6;
    expectNear(got.out, asDouble(want.out), kRounding, kRounding * maxOf(want.out), "out");
    expectNear(got.dPos, asDouble(want.dPos), kRounding, kRounding * maxOf(want.dPos), "dPos");
    // Inference (no workspace): the fused forward's other variant.
    expectNear(inferNerf(ctx(), fused, c.count, data), asDouble(want.out), kRounding, kRounding * maxOf(want.out),
               "inference out");
    const double gScale = maxAbs(referenceNerf(layered, c, data).grads);
    expectNear(got.grads, asDouble(want.grads), kGradRel, kGradAbsScale * gScale, "grads");
  }
  // The paper's network (8 x 256, a skip connection) runs layer by layer.
  EXPECT_FALSE(nerf::NerfMlp(ctx(), nerf::MlpConfig{}).fusedForward(false));
  // The compile bound counts the code an invocation spells out: the 13-level network above at 8
  // rows is 8 x 4224 multiply-adds unrolled, over kMaxFusedMultiplyAdds, and 8 x 624 in the block loop.
  nerf::MlpConfig wide;
  wide.depth = 1, wide.width = 64, wide.skipLayer = 0, wide.posDims = 26, wide.dirDims = 16, wide.featureWidth = 16;
  auto tuning = nerf::MlpTuning::forDevice(ctx());
  tuning.fused = 3, tuning.fusedRows = 8, tuning.fusedBlock = 4, tuning.fusedUnroll = 3;
  EXPECT_FALSE(nerf::NerfMlp(ctx(), wide, tuning).fusedForward(false));
  tuning.fusedUnroll = 0;
  EXPECT_TRUE(nerf::NerfMlp(ctx(), wide, tuning).fusedForward(false));
}

// The dense MLP forward and backward over `count` rows against the double reference; `gradRel`
// and `gradAbsScale` (of the largest gradient) bound the weight gradients, sums over every row.
void checkDense(Context& ctx, const nerf::DenseMlpConfig& cfg, uint32_t count, const nerf::MlpTuning& tuning,
                double gradRel, double gradAbsScale) {
  nerf::DenseMlp mlp(ctx, cfg, tuning);
  const uint32_t inStride = mlp.inputStride(), outStride = mlp.outputStride();
  auto params = mlp.initialParameters();
  auto in = features(count, cfg.inputs, inStride, 1);
  auto dOut = features(count, cfg.outputs, outStride, 2);
  auto pBuf = gpu::Buffer::of(ctx, params), inBuf = gpu::Buffer::of(ctx, in), dOutBuf = gpu::Buffer::of(ctx, dOut);
  gpu::Buffer out(ctx, uint64_t(count) * outStride * 4), grads(ctx, params.size() * 4), dIn(ctx, in.size() * 4);
  grads.zero();
  nerf::DenseMlp::Workspace ws(ctx, mlp, count);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    mlp.recordForward(rec, {count, inBuf, out}, pBuf, &ws);
    mlp.recordBackward(rec, {count, inBuf, out}, pBuf, {dOutBuf, grads, gpu::BufferRange(dIn)}, ws);
  });
  auto gOut = out.download<float>(size_t(count) * outStride), gGrads = grads.download<float>(params.size()),
       gIn = dIn.download<float>(in.size());

  const auto& s = mlp.shape();
  std::vector<double> rOut(size_t(count) * outStride, 0.0), rGrads(s.total, 0.0), rIn(in.size(), 0.0), x(cfg.inputs),
      d(cfg.outputs);
  for (uint32_t i = 0; i < count; ++i) {
    for (uint32_t k = 0; k < cfg.inputs; ++k) x[k] = in[size_t(i) * inStride + k];
    auto acts = ref::denseMlpForward<double>(s, params, x.data());
    for (uint32_t k = 0; k < cfg.outputs; ++k) rOut[size_t(i) * outStride + k] = acts.back()[k];  // padding: 0
    for (uint32_t k = 0; k < cfg.outputs; ++k) d[k] = dOut[size_t(i) * outStride + k];
    ref::denseMlpBackward(s, params, x.data(), acts, d.data(), rGrads, &rIn[size_t(i) * inStride]);
  }
  expectNear(gOut, rOut, kFwdRel, kFwdAbs, "out");
  expectNear(gGrads, rGrads, gradRel, gradAbsScale * maxAbs(rGrads), "grads");
  expectNear(gIn, rIn, kGradRel, kGradAbsScale * maxAbs(rIn), "dIn");
}

TEST_P(MlpDensePaths, ForwardAndBackwardMatchReference) {
  // The fit-image shape: gamma(u, v) with 10 levels (42 dims, stride 44) -> 2 x 32 -> rgb.
  checkDense(ctx(), nerf::DenseMlpConfig{42, 32, 2, 3, 17}, 333, tuning(), kGradRel, kGradAbsScale);
}

// The output layer's backward runs a lane per vec4 of outputs: 262,145 rows of 64 outputs are
// 4,194,320 lanes, more than 65,535 groups of 64 hold along x, the limit most devices have (it once
// refused such a batch). Narrow layers keep it quick. The gradients sum 262k rows in float atomics:
// error ~ sqrt(B) u to B u relative to the sum of magnitudes, the bound the batch over one binding
// takes (MlpNerf.BatchLargerThanOneBinding).
TEST_F(MlpNerf, DenseBackwardPastTheGroupCountOfOneAxis) {
  const nerf::DenseMlpConfig cfg{4, 8, 1, 61, 5};
  const uint32_t count = 262145;
  // On a device with more groups along x (NVIDIA's 2^31 - 1) the batch fits x alone: checked all the same.
  checkDense(ctx(), cfg, count, nerf::MlpTuning::forDevice(ctx()), 1e-2, 2e-3);
}

// A bias per row on the colour layer (NerfRows::colourBias) is the per-photo appearance vector a
// as input columns of that layer, through their weights W_a: the rows with bias a_photo W_a must
// give what the reference gives for the network whose direction input is [dir | a_photo] and whose
// colour layer has W_a as those columns' rows, both in the forward (layered, fused with and without
// the activations kept, each row its ray's photo's bias or every row one) and in the backward:
// the other parameters' gradients are that network's, and dColour is the reference's
// dL/d(colour pre-activation). Tolerances: the reference ones (kFwdRel/kFwdAbs, kGradRel with
// kGradAbsScale of the largest value) since the bias adds one more sum of dims products in float.
TEST_F(MlpNerf, ColourBiasIsTheVectorAsInputColumns) {
  constexpr uint32_t kDims = 8, kPhotos = 5, kRays = 40, kRows = 301;
  nerf::MlpConfig cfg;
  cfg.depth = 1, cfg.width = 32, cfg.skipLayer = 0, cfg.posDims = 16, cfg.dirDims = 16, cfg.featureWidth = 16;
  cfg.density = DensityActivation::TruncExp, cfg.seed = 5;
  auto tuning = nerf::MlpTuning::forDevice(ctx());
  tuning.fused = 0;
  nerf::NerfMlp layered(ctx(), cfg, tuning);
  tuning.fused = 3;
  nerf::NerfMlp fused(ctx(), cfg, tuning);
  layered.setChunkRows(128), fused.setChunkRows(128);  // chunks: the rows' rays bind at each chunk's first row
  const ref::NerfShape& narrow = layered.shape();
  const ref::NerfShape wide = ref::NerfShape::make(cfg.depth, cfg.width, 0, cfg.posDims, cfg.dirDims + kDims,
                                                   cfg.density, cfg.featureWidth);
  const uint32_t W2 = cfg.width / 2, colour = cfg.depth + 1;

  // The narrow network's parameters, a and W_a; the wide network holds the same, W_a as the rows of
  // the colour layer's extra inputs.
  const std::vector<float> params = layered.initialParameters();
  const std::vector<float> vectors = features(kPhotos, kDims, kDims, 11), weights = features(kDims, W2, W2, 12, 0.3f);
  std::vector<float> wideParams(wide.total, 0.0f);
  std::vector<size_t> wideOf(params.size());  // the wide index of each narrow parameter
  for (size_t l = 0; l < narrow.layers.size(); ++l) {
    const ref::DenseShape &n = narrow.layers[l], &w = wide.layers[l];
    for (uint32_t row = 0; row <= n.k4(); ++row)  // row k4: the bias
      for (uint32_t col = 0; col < n.n4(); ++col)
        wideOf[n.offset + size_t(row) * n.n4() + col] =
            (row == n.k4() ? w.biasOffset() : w.offset + size_t(row) * w.n4()) + col;
  }
  for (size_t i = 0; i < params.size(); ++i) wideParams[wideOf[i]] = params[i];
  const ref::DenseShape& wc = wide.layers[colour];
  for (uint32_t k = 0; k < kDims; ++k)
    for (uint32_t n = 0; n < W2; ++n) wideParams[wc.offset + size_t(wc.rowB(cfg.dirDims + k)) * wc.n4() + n] = weights[k * W2 + n];

  NerfCase c{cfg, kRows};
  const NerfData d = makeData(layered, c);
  std::vector<uint32_t> rowRay(kRows), rayTable(2 * kRays);
  for (uint32_t r = 0; r < kRows; ++r) rowRay[r] = ref::rngUint(3, r, 0) % kRays;
  for (uint32_t r = 0; r < kRays; ++r) rayTable[2 * r] = ref::rngUint(4, r, 0) % kPhotos, rayTable[2 * r + 1] = r;
  const auto biasDouble = ref::appearanceBias(vectors, weights, kDims, W2, 0, kPhotos);
  const std::vector<float> bias(biasDouble.begin(), biasDouble.end());

  // The wide reference, each row with its photo's vector (or one photo's for every row).
  auto reference = [&](std::optional<uint32_t> onePhoto) {
    NerfRef r{std::vector<double>(size_t(kRows) * 4), std::vector<double>(wide.total, 0.0), {}, {}};
    std::vector<double> dColour(size_t(kRows) * W2), pos(cfg.posDims), dir(cfg.dirDims + kDims), dDir(dir.size());
    for (uint32_t i = 0; i < kRows; ++i) {
      const uint32_t photo = onePhoto ? *onePhoto : rayTable[2 * rowRay[i]];
      for (uint32_t k = 0; k < cfg.posDims; ++k) pos[k] = d.pos[size_t(i) * layered.posStride() + k];
      for (uint32_t k = 0; k < cfg.dirDims; ++k) dir[k] = d.dir[size_t(i) * layered.dirStride() + k];
      for (uint32_t k = 0; k < kDims; ++k) dir[cfg.dirDims + k] = vectors[photo * kDims + k];
      auto fw = ref::nerfForward<double>(wide, wideParams, pos.data(), dir.data());
      for (int k = 0; k < 4; ++k) r.out[4 * i + k] = fw.out[k];
      std::array<double, 4> g{d.dOut[4 * i], d.dOut[4 * i + 1], d.dOut[4 * i + 2], d.dOut[4 * i + 3]};
    if (c.densityOnly) g[0] = g[1] = g[2] = 0.0;
      ref::nerfBackward(wide, wideParams, pos.data(), dir.data(), fw, g, r.grads, (double*)nullptr, dDir.data(),
                        &dColour[size_t(i) * W2]);
    }
    r.dDir = dColour;
    return r;
  };

  auto paramsBuf = gpu::Buffer::of(ctx(), params), pos = gpu::Buffer::of(ctx(), d.pos), dir = gpu::Buffer::of(ctx(), d.dir);
  auto dOut = gpu::Buffer::of(ctx(), d.dOut), biasBuf = gpu::Buffer::of(ctx(), bias);
  auto rowRayBuf = gpu::Buffer::of(ctx(), rowRay), rayTableBuf = gpu::Buffer::of(ctx(), rayTable);
  gpu::Buffer out(ctx(), size_t(kRows) * 16), grads(ctx(), params.size() * 4), dColour(ctx(), size_t(kRows) * W2 * 4);

  const NerfRef perRay = reference(std::nullopt);
  std::vector<double> narrowGrads(params.size());
  for (size_t i = 0; i < params.size(); ++i) narrowGrads[i] = perRay.grads[wideOf[i]];
  const double gScale = maxAbs(narrowGrads), dcScale = maxAbs(perRay.dDir);
  ASSERT_GT(dcScale, 0.0);
  for (nerf::NerfMlp* mlp : {&layered, &fused}) {
    SCOPED_TRACE(mlp == &fused ? "fused" : "layered");
    const nerf::RowBias rowBias{biasBuf, gpu::BufferRange(rowRayBuf), gpu::BufferRange(rayTableBuf)};
    nerf::NerfRows rows{kRows, pos, dir, out};
    rows.colourBias = rowBias;
    grads.zero();
    nerf::NerfMlp::Workspace ws(ctx(), *mlp, kRows);
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      mlp->recordForward(rec, rows, paramsBuf, &ws);
      nerf::NerfGradients gradients{dOut, grads};
      gradients.dColour = gpu::BufferRange(dColour);
      mlp->recordBackward(rec, rows, paramsBuf, gradients, ws);
    });
    expectNear(out.download<float>(size_t(kRows) * 4), perRay.out, kFwdRel, kFwdAbs, "out");
    expectNear(grads.download<float>(params.size()), narrowGrads, kGradRel, kGradAbsScale * gScale, "grads");
    expectNear(dColour.download<float>(size_t(kRows) * W2), perRay.dDir, kGradRel, kGradAbsScale * dcScale, "dColour");
    // Inference, each row its photo's bias.
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) { mlp->recordForward(rec, rows, paramsBuf, nullptr); });
    expectNear(out.download<float>(size_t(kRows) * 4), perRay.out, kFwdRel, kFwdAbs, "inference out");
  }
  // A render: every row adds one photo's bias (the table's row 0).
  const uint32_t photo = 3;
  const NerfRef one = reference(photo);
  auto oneBias = gpu::Buffer::of(ctx(), std::vector<float>(bias.begin() + photo * W2, bias.begin() + (photo + 1) * W2));
  for (nerf::NerfMlp* mlp : {&layered, &fused}) {
    SCOPED_TRACE(mlp == &fused ? "fused, one bias" : "layered, one bias");
    nerf::NerfRows rows{kRows, pos, dir, out};
    rows.colourBias = nerf::RowBias{oneBias};
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) { mlp->recordForward(rec, rows, paramsBuf, nullptr); });
    expectNear(out.download<float>(size_t(kRows) * 4), one.out, kFwdRel, kFwdAbs, "out");
  }
}

INSTANTIATE_TEST_SUITE_P(DwPaths, MlpNerfPaths,
                         testing::Values(DwPath{1, 1}, DwPath{0, 1}, DwPath{1, 0}, DwPath{0, 0}), dwPathName);
INSTANTIATE_TEST_SUITE_P(DwPaths, MlpDensePaths,
                         testing::Values(DwPath{1, 1}, DwPath{0, 1}, DwPath{1, 0}, DwPath{0, 0}), dwPathName);

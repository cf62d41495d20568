// The learned far field (src/models/common/far_field.h): its kernels and parts against the CPU
// reference (tests/reference/render/far_field.h), the reference against finite differences in double,
// and its start as a constant colour.
#include <cmath>
#include <vector>

#include "gpu/memory/buffer.h"
#include "models/common/far_field.h"
#include "nerf/optim/adam.h"
#include "reference/render/far_field.h"
#include "reference/rng.h"
#include "support/gpu_test.h"
#include "support/random_values.h"
#include "support/submit_once.h"

using namespace vknerf;

namespace {

// Forward: the hash grid sums 8 corners per level in float (|features| <= a few), then the MLP's
// chain of two dot products of length <= 64 (Higham: ~64 u sum|x w| ~ 4e-6 relative to the sum of
// magnitudes) and a sigmoid, whose slope <= 1/4 only shrinks errors: 1e-4 relative, 1e-5 absolute.
constexpr double kFwdRel = 1e-4, kFwdAbs = 1e-5;
// Gradients: an entry sums up to `kRays` per-ray products in float atomics (any order), each after the
// backward chain of the forward: ~(kRays + 64) u sum|terms|; with cancellation between rays the
// absolute part scales with the largest gradient of the buffer (as tests/unit/network/test_mlp.cpp).
constexpr double kGradRel = 1e-3, kGradAbsScale = 1e-4;
constexpr uint32_t kRays = 333;  // not a multiple of any workgroup size

struct Batch {
  std::vector<float> rays, color, dColor;  // 2 x vec4, vec4 (rgb, opacity), vec4 per ray
};

// Directions of every length and sign (including the six axes exactly: the grid's faces), colours
// with opacities across [0, 1] (0: all light reaches the far field; 1: none does).
Batch makeBatch(uint32_t n) {
  Batch b;
  b.rays.assign(size_t(n) * 8, 0.0f);
  b.color.assign(size_t(n) * 4, 0.0f);
  b.dColor.assign(size_t(n) * 4, 0.0f);
  const auto u = test::uniformFloats(size_t(n) * 8, 11);
  for (uint32_t i = 0; i < n; ++i) {
    float* d = &b.rays[i * 8 + 4];
    for (int k = 0; k < 3; ++k) d[k] = u[i * 8 + k] * (1.0f + 3.0f * float(i % 3));  // not unit length
    if (i < 6) d[0] = d[1] = d[2] = 0.0f, d[i / 2] = i % 2 ? -2.0f : 1.0f;
    b.rays[i * 8 + 7] = 5.0f;  // t_far: ignored
    for (int k = 0; k < 3; ++k) b.color[i * 4 + k] = 0.5f + 0.5f * u[i * 8 + 3 + k];
    b.color[i * 4 + 3] = i == 6 ? 1.0f : i == 7 ? 0.0f : float(ref::rng01(5, i, 0));
    for (int k = 0; k < 4; ++k) b.dColor[i * 4 + k] = 0.01f * u[i * 8 + 4 + k];
  }
  return b;
}

void expectNear(const std::vector<float>& gpu, const std::vector<double>& want, double rel, double abs,
                const char* what) {
  ASSERT_EQ(gpu.size(), want.size()) << what;
  for (size_t i = 0; i < want.size(); ++i) {
    ASSERT_TRUE(std::isfinite(gpu[i])) << what << "[" << i << "]";
    ASSERT_NEAR(gpu[i], want[i], abs + rel * std::fabs(want[i])) << what << "[" << i << "]";
  }
}

double maxAbs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

class FarFieldTest : public test::GpuTest {};

}  // namespace

TEST_F(FarFieldTest, ForwardAndBackwardMatchReference) {
  nerf::AdamConfig adam;
  models::LearnedFarField ff(ctx(), 512, 3, {0.3f, 0.6f, 0.9f}, adam, adam);
  const ref::FarFieldShape s = models::LearnedFarField::shape();
  // Parameters of a trained-looking field (the initial ones are a near-zero table and a zero output
  // layer, which would test nothing).
  auto table = test::uniformFloats(ref::hashGridParameterCount(s.grid), 21, -0.5f, 0.5f);
  auto mlp = test::uniformFloats(s.mlp.total, 22, -0.3f, 0.3f);
  ff.tableParams().upload(table);
  ff.mlpParams().upload(mlp);
  ff.tableGrads().zero();
  ff.mlpGrads().zero();
  const Batch b = makeBatch(kRays);
  auto rays = gpu::Buffer::of(ctx(), b.rays), color = gpu::Buffer::of(ctx(), b.color),
       dColor = gpu::Buffer::of(ctx(), b.dColor);
  gpu::Buffer bg = gpu::Buffer::zeros(ctx(), kRays * 16);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    ff.recordForward(rec, kRays, rays, bg, true);
    ff.recordBackward(rec, kRays, bg, color, dColor);
  });
  const auto gBg = bg.download<float>(kRays * 4);
  const auto gTable = ff.tableGrads().download<float>(table.size());
  const auto gMlp = ff.mlpGrads().download<float>(mlp.size());

  std::vector<double> rBg(kRays * 4, 0.0), rTable(table.size(), 0.0), rMlp(mlp.size(), 0.0);
  for (uint32_t i = 0; i < kRays; ++i) {
    const double d[3] = {b.rays[i * 8 + 4], b.rays[i * 8 + 5], b.rays[i * 8 + 6]};
    const auto c = ref::farFieldColor<double>(s, table, mlp, d);
    for (int k = 0; k < 3; ++k) rBg[i * 4 + k] = c[k];  // w: 0
    const double dc[3] = {b.dColor[i * 4], b.dColor[i * 4 + 1], b.dColor[i * 4 + 2]};
    ref::farFieldBackward<double>(s, table, mlp, d, b.color[i * 4 + 3], dc, rTable, rMlp);
  }
  expectNear(gBg, rBg, kFwdRel, kFwdAbs, "background");
  expectNear(gTable, rTable, kGradRel, kGradAbsScale * maxAbs(rTable), "table grads");
  expectNear(gMlp, rMlp, kGradRel, kGradAbsScale * maxAbs(rMlp), "mlp grads");
}

TEST_F(FarFieldTest, OpaqueRaysTeachNothing) {
  // Every ray opaque: no light reaches the far field, so no parameter gets a gradient.
  nerf::AdamConfig adam;
  models::LearnedFarField ff(ctx(), 64, 3, {0.5f, 0.5f, 0.5f}, adam, adam);
  const ref::FarFieldShape s = models::LearnedFarField::shape();
  ff.tableParams().upload(test::uniformFloats(ref::hashGridParameterCount(s.grid), 21, -0.5f, 0.5f));
  ff.mlpParams().upload(test::uniformFloats(s.mlp.total, 22, -0.3f, 0.3f));
  ff.tableGrads().zero();
  ff.mlpGrads().zero();
  Batch b = makeBatch(64);
  for (uint32_t i = 0; i < 64; ++i) b.color[i * 4 + 3] = 1.0f;
  auto rays = gpu::Buffer::of(ctx(), b.rays), color = gpu::Buffer::of(ctx(), b.color),
       dColor = gpu::Buffer::of(ctx(), b.dColor);
  gpu::Buffer bg = gpu::Buffer::zeros(ctx(), 64 * 16);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    ff.recordForward(rec, 64, rays, bg, true);
    ff.recordBackward(rec, 64, bg, color, dColor);
  });
  for (float g : ff.tableGrads().download<float>(ref::hashGridParameterCount(s.grid))) ASSERT_EQ(g, 0.0f);
  for (float g : ff.mlpGrads().download<float>(s.mlp.total)) ASSERT_EQ(g, 0.0f);
}

TEST_F(FarFieldTest, StartsAsTheConstantColour) {
  // The initial parameters give `initial` (clamped to [0.05, 0.95]) in every direction.
  models::LearnedFarField ff(ctx(), 128, 9, {1.0f, 0.25f, 0.0f}, std::nullopt, std::nullopt);
  const Batch b = makeBatch(128);
  auto rays = gpu::Buffer::of(ctx(), b.rays);
  gpu::Buffer bg = gpu::Buffer::zeros(ctx(), 128 * 16);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) { ff.recordForward(rec, 128, rays, bg, false); });
  const auto got = bg.download<float>(128 * 4);
  const float want[3] = {0.95f, 0.25f, 0.05f};
  // exp/log round trip of the sigmoid in float: a few ulps.
  for (uint32_t i = 0; i < 128; ++i)
    for (int k = 0; k < 3; ++k) ASSERT_NEAR(got[i * 4 + k], want[k], 1e-6f) << "ray " << i << " channel " << k;
}

TEST(FarFieldReference, GradientMatchesFiniteDifferences) {
  // L = dColor . (T_final bg(d)) for a few rays, in double: the reference's gradient against central
  // differences at entries the rays touch (the table's entries at their corners) and at every MLP
  // parameter of the output layer and a sample of the hidden one.
  const ref::FarFieldShape s = models::LearnedFarField::shape();
  std::vector<double> table(ref::hashGridParameterCount(s.grid)), mlp(s.mlp.total);
  const auto t0 = test::uniformFloats(table.size(), 31, -0.5f, 0.5f), m0 = test::uniformFloats(mlp.size(), 32, -0.3f, 0.3f);
  std::copy(t0.begin(), t0.end(), table.begin());
  std::copy(m0.begin(), m0.end(), mlp.begin());
  const Batch b = makeBatch(12);
  auto loss = [&](const std::vector<double>& t, const std::vector<double>& m) {
    double L = 0;
    for (uint32_t i = 0; i < 12; ++i) {
      const double d[3] = {b.rays[i * 8 + 4], b.rays[i * 8 + 5], b.rays[i * 8 + 6]};
      const auto c = ref::farFieldColor<double>(s, t, m, d);
      for (int k = 0; k < 3; ++k) L += b.dColor[i * 4 + k] * (1.0 - b.color[i * 4 + 3]) * c[k];
    }
    return L;
  };
  std::vector<double> gTable(table.size(), 0.0), gMlp(mlp.size(), 0.0);
  for (uint32_t i = 0; i < 12; ++i) {
    const double d[3] = {b.rays[i * 8 + 4], b.rays[i * 8 + 5], b.rays[i * 8 + 6]};
    const double dc[3] = {b.dColor[i * 4], b.dColor[i * 4 + 1], b.dColor[i * 4 + 2]};
    ref::farFieldBackward<double>(s, table, mlp, d, double(b.color[i * 4 + 3]), dc, gTable, gMlp);
  }
  // Central differences in double with h = 1e-6: truncation O(h^2 f''') ~ 1e-12 and rounding
  // ~ eps |L| / h ~ 1e-10 for |L| ~ 1e-2; the loss is smooth in every parameter here except at ReLU
  // kinks, which a random point misses almost surely.
  const double h = 1e-6, tol = 1e-8;
  auto check = [&](std::vector<double>& p, const std::vector<double>& g, size_t k, bool isTable) {
    const double keep = p[k];
    p[k] = keep + h;
    const double up = isTable ? loss(p, mlp) : loss(table, p);
    p[k] = keep - h;
    const double down = isTable ? loss(p, mlp) : loss(table, p);
    p[k] = keep;
    EXPECT_NEAR(g[k], (up - down) / (2 * h), tol + 1e-6 * std::fabs(g[k])) << (isTable ? "table " : "mlp ") << k;
  };
  size_t touched = 0;
  for (size_t k = 0; k < table.size(); ++k)
    if (gTable[k] != 0.0 && touched++ < 200) check(table, gTable, k, true);
  EXPECT_GT(touched, 50u);  // the rays touch entries on every level
  for (size_t k = 0; k < mlp.size(); k += 7) check(mlp, gMlp, k, false);
}

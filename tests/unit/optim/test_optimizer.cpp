// adam.comp against the CPU reference (tests/reference/optim/adam.h).
#include <algorithm>
#include <cmath>
#include <random>
#include <span>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "models/common/trainable_parameters.h"
#include "nerf/optim/adam.h"
#include "reference/optim/adam.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

ref::AdamParams<double> refParams(const nerf::AdamConfig& c) {
  return {double(c.beta1), double(c.beta2), double(c.epsilon),
          c.skipZeroGradientsFrom == nerf::AdamConfig::kNever ? SIZE_MAX : size_t(c.skipZeroGradientsFrom)};
}

// Device state of one optimisation problem next to its double-precision twin.
struct Problem {
  std::vector<float> p, m, v;
  std::vector<double> rp, rm, rv;
  gpu::Buffer pb, gb, mb, vb;
  Problem(Context& ctx, std::vector<float> p0, std::vector<float> m0, std::vector<float> v0)
      : p(p0), m(m0), v(v0), rp(p0.begin(), p0.end()), rm(m0.begin(), m0.end()), rv(v0.begin(), v0.end()),
        pb(gpu::Buffer::of(ctx, p0)), gb(ctx, 4 * p0.size()), mb(gpu::Buffer::of(ctx, m0)),
        vb(gpu::Buffer::of(ctx, v0)) {}

  // One step on both; returns the device gradient buffer after the step.
  std::vector<float> step(Context& ctx, nerf::Adam& adam, const std::vector<float>& g, uint32_t t, float lr) {
    gb.upload(g);
    test::submitOnce(ctx, [&](gpu::Recorder& rec) {
      adam.record(rec, {uint32_t(p.size()), pb, gb, mb, vb}, t, lr);
    });
    std::vector<double> rg(g.begin(), g.end());
    ref::adamStep<double>(rp, rg, rm, rv, t, double(lr), refParams(adam.config()));
    p = pb.download<float>();
    m = mb.download<float>();
    v = vb.download<float>();
    return gb.download<float>();
  }
};

std::vector<float> randomVector(size_t n, uint32_t seed, float scale, float zeroFraction = 0) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(-1, 1), z(0, 1);
  std::vector<float> out(n);
  for (auto& x : out) x = z(gen) < zeroFraction ? 0.0f : scale * u(gen);
  return out;
}

// Float error of one device step, relative to the double reference:
// - the update ratio mhat / (sqrt(vhat) + eps) is bounded by (1 - b1) / sqrt(1 - b2) (about 3.2 for
//   the defaults, 1 at t = 1) and is computed with ~10 roundings, and m may cancel (its absolute
//   error is a few ulp of the gradients feeding it, and sqrt(v) is at least of that order), so
//   the update is off by at most ~lr * 3.2 * 16 * 2^-24 < 4e-6 lr;
// - p - update rounds once more: half an ulp of p.
// Errors of successive steps add, hence the per-step bound times the number of steps.
::testing::AssertionResult paramNear(float gpu, double ref, double lr, int steps) {
  return test::near(gpu, ref, steps * 1.2e-7, steps * 4e-6 * lr);
}

class Adam : public test::GpuTest {};

}  // namespace

TEST(AdamReference, FirstStepIsLearningRateTimesSign) {
  // Bias correction at t = 1: mhat = g and vhat = g^2, so the update is lr g / (|g| + eps).
  std::vector<double> p = {1.0, -2.0, 0.5, 3.0}, g = {1e-3, -4.0, 1e-7, 0.0}, m(4, 0.0), v(4, 0.0);
  ref::AdamParams<double> a{0.9, 0.999, 1e-15};
  ref::adamStep<double>(p, g, m, v, 1, 0.01, a);
  EXPECT_NEAR(p[0], 1.0 - 0.01, 1e-12);
  EXPECT_NEAR(p[1], -2.0 + 0.01, 1e-12);
  EXPECT_NEAR(p[2], 0.5 - 0.01, 1e-9);  // eps / |g| = 1e-8
  EXPECT_EQ(p[3], 3.0);                 // zero gradient, zero moments: no move, no NaN
  for (double x : g) EXPECT_EQ(x, 0.0);
}

TEST(AdamReference, MinimisesAQuadratic) {
  // f(x) = sum (x_i - a_i)^2 from x = 0: Adam with lr 0.05 settles within a few lr of the minimum.
  std::vector<double> a = {1.0, -0.5, 2.0}, x(3, 0.0), m(3, 0.0), v(3, 0.0), g(3);
  for (uint32_t t = 1; t <= 2000; ++t) {
    for (int i = 0; i < 3; ++i) g[i] = 2 * (x[i] - a[i]);
    ref::adamStep<double>(x, g, m, v, t, 0.05, {});
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(x[i], a[i], 0.05);
}

TEST(AdamReference, LearningRateDecaySchedule) {
  nerf::AdamConfig c;
  c.initialLearningRate = 5e-4f;
  c.decayRate = 0.1f;
  c.decaySteps = 250000;
  EXPECT_FLOAT_EQ(c.learningRate(0), 5e-4f);
  EXPECT_FLOAT_EQ(c.learningRate(250000), 5e-5f);
  EXPECT_FLOAT_EQ(c.learningRate(125000), float(5e-4 * std::sqrt(0.1)));
  EXPECT_FLOAT_EQ(c.learningRate(500000), 5e-6f);
  EXPECT_FLOAT_EQ(c.learningRate(1000), float(ref::decayedLearningRate<double>(5e-4, 0.1, 250000, 1000)));
  EXPECT_LT(c.learningRate(1001), c.learningRate(1000));  // continuous, not staircase
  c.decayRate = 1;
  EXPECT_FLOAT_EQ(c.learningRate(123456), 5e-4f);
}

TEST(AdamReference, LearningRateHoldsAfterTheDecayEnds) {
  nerf::AdamConfig c;
  c.initialLearningRate = 1e-2f;
  c.decayRate = 0.1f;
  c.decaySteps = 4000;
  c.decayEndStep = 4000;
  EXPECT_FLOAT_EQ(c.learningRate(2000), float(ref::decayedLearningRate<double>(1e-2, 0.1, 4000, 2000)));
  EXPECT_FLOAT_EQ(c.learningRate(4000), 1e-3f);
  EXPECT_FLOAT_EQ(c.learningRate(16000), 1e-3f);  // without the hold: 1e-6
  EXPECT_FLOAT_EQ(c.learningRate(UINT32_MAX), 1e-3f);

  // A training configuration ends its decay at its final rate: that is what its fields promise.
  TrainConfig t;
  t.learningRate = 2e-3f;
  t.learningRateFinal = 2e-4f;
  t.decaySteps = 100;
  const nerf::AdamConfig a = models::adamConfigOf(t);
  EXPECT_FLOAT_EQ(a.learningRate(100), 2e-4f);
  EXPECT_FLOAT_EQ(a.learningRate(1000), 2e-4f);
  EXPECT_GT(a.learningRate(99), a.learningRate(100));
  // A rising schedule holds at its final rate too.
  t.learningRateFinal = 4e-3f;
  EXPECT_FLOAT_EQ(models::adamConfigOf(t).learningRate(5000), 4e-3f);
}

TEST_F(Adam, OneStepMatchesReference) {
  const size_t n = 1003;  // 250 vec4 lanes + 3 leftovers; not a multiple of the workgroup either
  nerf::AdamConfig cfg;
  cfg.epsilon = 1e-15f;
  nerf::Adam adam(ctx(), cfg);
  Problem pr(ctx(), randomVector(n, 1, 1), std::vector<float>(n), std::vector<float>(n));
  auto g = randomVector(n, 2, 0.1f, 0.1f);
  const float lr = 0.01f;
  auto gAfter = pr.step(ctx(), adam, g, 1, lr);
  for (size_t i = 0; i < n; ++i) {
    ASSERT_TRUE(paramNear(pr.p[i], pr.rp[i], lr, 1)) << i;
    ASSERT_TRUE(test::near(pr.m[i], pr.rm[i], 2.4e-7, 0)) << i;  // one product and sum of two products
    ASSERT_TRUE(test::near(pr.v[i], pr.rv[i], 3.6e-7, 0)) << i;
    ASSERT_EQ(gAfter[i], 0.0f) << i;
    // Bias correction at t = 1: the first update is lr * sign(g) (eps is negligible here).
    float sign = g[i] > 0 ? 1.0f : g[i] < 0 ? -1.0f : 0.0f;
    float start = randomVector(n, 1, 1)[i];
    ASSERT_NEAR(start - pr.p[i], lr * sign, 1e-6) << i;
  }
}

TEST_F(Adam, SeveralStepsMatchReference) {
  const size_t n = 642;  // 160 vec4 lanes + 2 leftovers
  nerf::AdamConfig cfg;
  cfg.beta2 = 0.99f;
  cfg.epsilon = 1e-15f;
  cfg.initialLearningRate = 1e-2f;
  cfg.decayRate = 0.1f;
  cfg.decaySteps = 10;
  nerf::Adam adam(ctx(), cfg);
  Problem pr(ctx(), randomVector(n, 3, 1), std::vector<float>(n), std::vector<float>(n));
  const int steps = 6;
  for (int t = 1; t <= steps; ++t) {
    // Gradients of changing sign and scale, some exactly zero: m cancels, v keeps the history.
    auto g = randomVector(n, 10 + t, t % 2 ? 1.0f : 1e-3f, 0.2f);
    auto gAfter = pr.step(ctx(), adam, g, t, cfg.learningRate(t));
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(gAfter[i], 0.0f);
  }
  double maxErr = 0;
  for (size_t i = 0; i < n; ++i) {
    ASSERT_TRUE(paramNear(pr.p[i], pr.rp[i], cfg.initialLearningRate, steps)) << i;
    // m: a few roundings per step of sums that may cancel: relative to the largest gradient (1).
    ASSERT_TRUE(test::near(pr.m[i], pr.rm[i], steps * 2.4e-7, steps * 1.2e-7)) << i;
    ASSERT_TRUE(test::near(pr.v[i], pr.rv[i], steps * 3.6e-7, 0)) << i;  // sums of positive terms
    maxErr = std::max(maxErr, std::fabs(pr.p[i] - pr.rp[i]));
  }
  std::printf("adam %d steps: max |p_gpu - p_ref| = %.3g (lr %.3g)\n", steps, maxErr, cfg.initialLearningRate);
}

// From skipZeroGradientsFrom on (0: all; 100: a table whose first levels take the dense step), a
// parameter with a zero gradient keeps p, m and v bit for bit; before it, and every parameter with
// a gradient, take the reference's step.
TEST_F(Adam, SkipsParametersWithZeroGradient) {
  const size_t n = 203;  // leftovers included
  auto p0 = randomVector(n, 4, 1);
  auto m0 = randomVector(n, 5, 0.1f);
  auto v0 = randomVector(n, 6, 0.01f);
  for (auto& x : v0) x = std::fabs(x);
  // Whole zero vec4 rows (the sparse hash-grid case) before and past 100, single zeros, and a zero leftover.
  auto g = randomVector(n, 7, 0.5f, 0.3f);
  for (size_t i = 40; i < 48; ++i) g[i] = 0;
  for (size_t i = 120; i < 128; ++i) g[i] = 0;
  g[n - 2] = 0;
  const float lr = 1e-3f;
  for (const uint32_t from : {0u, 100u}) {
    SCOPED_TRACE(testing::Message() << "skipped from " << from);
    nerf::AdamConfig cfg;
    cfg.skipZeroGradientsFrom = from;
    nerf::Adam adam(ctx(), cfg);
    Problem pr(ctx(), p0, m0, v0);
    auto gAfter = pr.step(ctx(), adam, g, 3, lr);
    int skipped = 0;
    for (size_t i = 0; i < n; ++i) {
      ASSERT_EQ(gAfter[i], 0.0f);
      if (g[i] == 0.0f && i >= from) {
        ++skipped;
        ASSERT_EQ(pr.p[i], p0[i]) << i;  // bit for bit untouched
        ASSERT_EQ(pr.m[i], m0[i]) << i;
        ASSERT_EQ(pr.v[i], v0[i]) << i;
      } else {
        ASSERT_TRUE(paramNear(pr.p[i], pr.rp[i], lr, 1)) << i;
        ASSERT_NE(pr.p[i], p0[i]) << i;  // a zero gradient before `from`: its momentum moves it
        ASSERT_NE(pr.m[i], m0[i]) << i;
      }
    }
    EXPECT_GT(skipped, from ? 25 : 50);
  }
  nerf::AdamConfig bad;
  bad.skipZeroGradientsFrom = 6;
  EXPECT_THROW(nerf::Adam(ctx(), bad), Error);
}

// The sparse part over many workgroups of the touched-list pass (each lists 1024 vec4s): a table
// of 12000 vec4s sparse from vec4 1024 on, its gradients zero in whole vec4 rows (80%, scattered as
// a hash level's untouched entries are) and in single components, a new pattern every step: each
// step's list is built anew (its length reset), every touched vec4 is stepped once, and the result
// is the reference's (the parameters within paramNear, the untouched ones bit for bit).
TEST_F(Adam, SparsePartStepsEachTouchedParameterOnce) {
  const size_t n = 4 * 12000;
  nerf::AdamConfig cfg;
  cfg.skipZeroGradientsFrom = 4 * 1024;
  nerf::Adam adam(ctx(), cfg);
  auto v0 = randomVector(n, 6, 0.01f);
  for (auto& x : v0) x = std::fabs(x);
  Problem pr(ctx(), randomVector(n, 4, 1), randomVector(n, 5, 0.1f), v0);
  const float lr = 1e-3f;
  for (uint32_t t = 1; t <= 3; ++t) {
    SCOPED_TRACE(testing::Message() << "step " << t);
    auto g = randomVector(n, 20 + t, 0.5f, 0.1f);
    std::mt19937 gen(30 + t);
    for (size_t row = 0; row < n / 4; ++row)
      if (gen() % 5 != 0)
        for (size_t k = 0; k < 4; ++k) g[4 * row + k] = 0;
    const auto before = pr.p;
    auto gAfter = pr.step(ctx(), adam, g, t, lr);
    size_t stepped = 0;
    for (size_t i = 0; i < n; ++i) {
      ASSERT_EQ(gAfter[i], 0.0f) << i;
      ASSERT_TRUE(paramNear(pr.p[i], pr.rp[i], lr, t)) << i;
      if (g[i] == 0.0f && i >= cfg.skipZeroGradientsFrom) ASSERT_EQ(pr.p[i], before[i]) << i;
      stepped += pr.p[i] != before[i];
    }
    EXPECT_GT(stepped, n / 5);  // the test must see steps
  }
}

// AdamState::stepped: only the listed parts are stepped, each as the reference steps it (its skip
// index counted from the whole set's start); outside them p, m, v and even a nonzero gradient keep
// their bits. The parts end with leftovers (not whole vec4s), and skipZeroGradientsFrom falls
// inside the second, so a part can be half dense, half through the touched list.
TEST_F(Adam, StepsOnlyTheStatesParts) {
  const size_t n = 700;
  // Starts at multiples of 64 floats: 256 bytes, the largest offset alignment Vulkan allows.
  const std::vector<nerf::ParameterRange> parts = {{0, 37}, {128, 203}, {448, 65}};
  auto p0 = randomVector(n, 4, 1), m0 = randomVector(n, 5, 0.1f), v0 = randomVector(n, 6, 0.01f);
  for (auto& x : v0) x = std::fabs(x);
  const auto g = randomVector(n, 7, 0.5f, 0.3f);
  const float lr = 1e-3f;
  for (const uint32_t from : {nerf::AdamConfig::kNever, 0u, 256u}) {
    SCOPED_TRACE(testing::Message() << "skipped from " << from);
    nerf::AdamConfig cfg;
    cfg.skipZeroGradientsFrom = from;
    nerf::Adam adam(ctx(), cfg);
    gpu::Buffer pb = gpu::Buffer::of(ctx(), p0), gb = gpu::Buffer::of(ctx(), g), mb = gpu::Buffer::of(ctx(), m0),
                vb = gpu::Buffer::of(ctx(), v0);
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) { adam.record(rec, {uint32_t(n), pb, gb, mb, vb, parts}, 2, lr); });
    const auto p = pb.download<float>(), gAfter = gb.download<float>(), m = mb.download<float>(), v = vb.download<float>();
    std::vector<double> rp(p0.begin(), p0.end()), rg(g.begin(), g.end()), rm(m0.begin(), m0.end()), rv(v0.begin(), v0.end());
    std::vector<bool> inside(n, false);
    for (const nerf::ParameterRange& part : parts) {
      ref::AdamParams<double> a = refParams(cfg);
      a.skipZeroGradientsFrom = from > part.first ? from - part.first : 0;
      auto span = [&](std::vector<double>& x) { return std::span<double>(x).subspan(part.first, part.count); };
      ref::adamStep<double>(span(rp), span(rg), span(rm), span(rv), 2, double(lr), a);
      for (uint32_t i = part.first; i < part.first + part.count; ++i) inside[i] = true;
    }
    size_t moved = 0;
    for (size_t i = 0; i < n; ++i) {
      if (!inside[i]) {
        ASSERT_EQ(p[i], p0[i]) << i;
        ASSERT_EQ(m[i], m0[i]) << i;
        ASSERT_EQ(v[i], v0[i]) << i;
        ASSERT_EQ(gAfter[i], g[i]) << i;
        continue;
      }
      ASSERT_TRUE(paramNear(p[i], rp[i], lr, 1)) << i;
      ASSERT_EQ(gAfter[i], 0.0f) << i;
      if (rp[i] == double(p0[i])) ASSERT_EQ(p[i], p0[i]) << i;  // a skipped zero gradient, bit for bit
      moved += p[i] != p0[i];
    }
    EXPECT_GT(moved, size_t(200));
  }
  // Parts that overlap, come out of order, end past the set or start off a bound offset are errors.
  nerf::Adam adam(ctx(), {});
  gpu::Buffer pb(ctx(), 4 * n), gb(ctx(), 4 * n), mb(ctx(), 4 * n), vb(ctx(), 4 * n);
  for (const std::vector<nerf::ParameterRange>& bad : std::vector<std::vector<nerf::ParameterRange>>{
           {{0, 100}, {64, 10}}, {{128, 10}, {0, 10}}, {{640, 61}}, {{2, 10}}}) {
    SCOPED_TRACE(testing::Message() << "first part [" << bad[0].first << ", +" << bad[0].count << ")");
    EXPECT_THROW(
        test::submitOnce(ctx(), [&](gpu::Recorder& rec) { adam.record(rec, {uint32_t(n), pb, gb, mb, vb, bad}, 1, 1e-3f); }),
        Error);
  }
}

TEST_F(Adam, ExtremeGradientsStayFinite) {
  // Zero gradient with zero moments and the tiniest epsilon: 0 / (0 + eps) = 0, never NaN. Huge and
  // subnormal-squared gradients: v may overflow to inf or flush to 0, the update stays finite.
  const size_t n = 9;
  nerf::AdamConfig cfg;
  cfg.epsilon = 1e-15f;
  nerf::Adam adam(ctx(), cfg);
  std::vector<float> p0(n, 0.25f);
  Problem pr(ctx(), p0, std::vector<float>(n), std::vector<float>(n));
  std::vector<float> g = {0.0f, -0.0f, 1e-30f, -1e-30f, 1e20f, -1e30f, 3.4e38f, 1e-45f, 0.0f};
  for (uint32_t t = 1; t <= 3; ++t) pr.step(ctx(), adam, g, t, 1e-2f);
  for (size_t i = 0; i < n; ++i) {
    EXPECT_TRUE(std::isfinite(pr.p[i])) << i;
    EXPECT_TRUE(std::isfinite(pr.m[i])) << i;
    EXPECT_FALSE(std::isnan(pr.v[i])) << i;
    EXPECT_LE(std::fabs(pr.p[i] - 0.25f), 3 * 1e-2f * 3.2f) << i;  // Adam's step bound
  }
  EXPECT_EQ(pr.p[0], 0.25f);
  EXPECT_EQ(pr.p[8], 0.25f);
  EXPECT_EQ(pr.m[0], 0.0f);
  EXPECT_EQ(pr.v[0], 0.0f);
}

TEST_F(Adam, EmptyStepAndBadArguments) {
  nerf::Adam adam(ctx(), {});
  auto b = gpu::Buffer::of(ctx(), std::vector<float>(8, 1.0f));
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    adam.record(rec, {0, b, b, b, b}, 1, 0.1f);                                                // count 0: records nothing
    EXPECT_THROW(adam.record(rec, {8, b, b, b, b}, 0, 0.1f), Error);                           // steps are 1-based
    EXPECT_THROW(adam.record(rec, {4, gpu::BufferRange(b, 4, 16), b, b, b}, 1, 0.1f), Error);  // misaligned
    EXPECT_THROW(adam.record(rec, {9, b, b, b, b}, 1, 0.1f), Error);  // more parameters than the buffers hold
  });
  for (float x : b.download<float>()) EXPECT_EQ(x, 1.0f);
  nerf::AdamConfig bad;
  bad.epsilon = 0;
  EXPECT_THROW(nerf::Adam(ctx(), bad), Error);
  bad = {};
  bad.beta2 = 1.0f;
  EXPECT_THROW(nerf::Adam(ctx(), bad), Error);
}

TEST_F(Adam, SubRangesAndTinyCounts) {
  // Parameters at an offset inside larger buffers, surrounded by sentinels that must survive;
  // counts below 4 (no vec4 part), exactly 4 (no leftovers) and 5.
  nerf::AdamConfig cfg;
  nerf::Adam adam(ctx(), cfg);
  for (uint32_t count : {1u, 3u, 4u, 5u}) {
    // floats: 16, or the device's storage offset alignment where larger (up to 256 bytes on GPUs)
    const uint32_t offset = std::max<uint32_t>(16, uint32_t(ctx().properties().limits.minStorageBufferOffsetAlignment / 4)),
                   total = offset + count + 9;
    auto p = randomVector(total, count, 1), g = randomVector(total, 100 + count, 1);
    std::vector<float> mv(total, 0.5f);
    auto pb = gpu::Buffer::of(ctx(), p), gb = gpu::Buffer::of(ctx(), g), mb = gpu::Buffer::of(ctx(), mv),
         vb = gpu::Buffer::of(ctx(), mv);
    auto sub = [&](const gpu::Buffer& b) { return gpu::BufferRange(b, 4 * offset, 4 * count); };
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      adam.record(rec, {count, sub(pb), sub(gb), sub(mb), sub(vb)}, 2, 0.01f);
    });
    std::vector<double> rp(p.begin() + offset, p.begin() + offset + count), rg(g.begin() + offset, g.begin() + offset + count),
        rm(count, 0.5), rv(count, 0.5);
    ref::adamStep<double>(rp, rg, rm, rv, 2, 0.01, refParams(cfg));
    auto po = pb.download<float>(), go = gb.download<float>(), mo = mb.download<float>();
    for (uint32_t i = 0; i < total; ++i) {
      bool inside = i >= offset && i < offset + count;
      if (!inside) {
        ASSERT_EQ(po[i], p[i]) << count << ": " << i;
        ASSERT_EQ(go[i], g[i]) << count << ": " << i;
        ASSERT_EQ(mo[i], 0.5f) << count << ": " << i;
      } else {
        ASSERT_TRUE(paramNear(po[i], rp[i - offset], 0.01, 1)) << count << ": " << i;
        ASSERT_TRUE(test::near(mo[i], rm[i - offset], 2.4e-7, 0)) << count << ": " << i;
        ASSERT_EQ(go[i], 0.0f);
      }
    }
  }
}

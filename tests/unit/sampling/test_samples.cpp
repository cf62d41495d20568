// sample_stratified.comp and sample_pdf.comp against the CPU reference (tests/reference/sampling/samplers.h).
// No gradients flow through sample positions, so there is no finite-difference check here.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "nerf/rays/rays.h"
#include "nerf/sampling/samplers.h"
#include "reference/rng.h"
#include "reference/sampling/samplers.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

constexpr double kEps = FLT_EPSILON;

// (t_near, t_far) per ray, packed as rays.comp writes them; origin and direction are irrelevant.
std::vector<float> packRays(const std::vector<std::pair<float, float>>& bounds) {
  std::vector<float> out;
  for (auto [tn, tf] : bounds) out.insert(out.end(), {0.1f, 0.2f, 0.3f, tn, 0.f, 0.f, -1.f, tf});
  return out;
}

std::vector<float> runStratified(Context& ctx, const std::vector<std::pair<float, float>>& bounds, uint32_t n,
                                 uint32_t seed, bool jitter) {
  uint32_t numRays = uint32_t(bounds.size());
  auto rays = gpu::Buffer::of(ctx, packRays(bounds.empty() ? decltype(bounds){{0, 0}} : bounds));
  gpu::Buffer samples(ctx, std::max<VkDeviceSize>(numRays * n * nerf::kSampleBytes, 16));
  nerf::StratifiedSampler sampler(ctx);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    sampler.record(rec, {rays, numRays}, n, {seed, jitter}, samples);
  });
  return samples.download<float>(size_t(numRays) * n * 2);
}

struct PdfCase {
  std::vector<std::pair<float, float>> bounds;
  std::vector<float> coarseT;   // nCoarse per ray
  std::vector<float> weights;   // nCoarse per ray
  uint32_t nCoarse = 0, nFine = 0, seed = 7;
  bool jitter = false;
  float padding = 0;
};

std::vector<float> runPdf(Context& ctx, const PdfCase& c) {
  uint32_t numRays = uint32_t(c.bounds.size()), nOut = c.nCoarse + c.nFine;
  // Coarse samples as the stratified pass hands them over: (t, delta), deltas closing at t_far.
  std::vector<float> coarse;
  for (uint32_t r = 0; r < numRays; ++r) {
    std::vector<float> ts(c.coarseT.begin() + r * c.nCoarse, c.coarseT.begin() + (r + 1) * c.nCoarse);
    for (auto s : ref::closeSegments(ts, c.bounds[r].second)) coarse.insert(coarse.end(), {s.t, s.delta});
  }
  coarse.resize(std::max<size_t>(coarse.size(), 4));
  std::vector<float> weights = c.weights;
  weights.resize(std::max<size_t>(weights.size(), 4));
  auto rays = gpu::Buffer::of(ctx, packRays(c.bounds));
  auto coarseBuf = gpu::Buffer::of(ctx, coarse);
  auto weightBuf = gpu::Buffer::of(ctx, weights);
  gpu::Buffer merged(ctx, std::max<VkDeviceSize>(numRays * nOut * nerf::kSampleBytes, 16));
  nerf::PdfSampler sampler(ctx);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    sampler.record(rec, {rays, numRays}, {coarseBuf, weightBuf, c.nCoarse}, {c.nFine, {c.seed, c.jitter}, c.padding},
                   merged);
  });
  return merged.download<float>(size_t(numRays) * nOut * 2);
}

template <class T> std::vector<T> slice(const std::vector<float>& v, size_t first, size_t n) {
  return std::vector<T>(v.begin() + first, v.begin() + first + n);
}

template <class T>
std::vector<ref::Sample<T>> refPdf(const PdfCase& c, uint32_t r) {
  return ref::importanceSamples<T>(c.bounds[r].first, c.bounds[r].second, slice<T>(c.coarseT, r * c.nCoarse, c.nCoarse),
                                   slice<T>(c.weights, r * c.nCoarse, c.nCoarse), c.nFine, c.seed, r, c.jitter,
                                   T(c.padding));
}

// Every value finite, t's sorted, deltas >= 0 and each one reaching the next t (the last one t_far).
// The shader computes delta as the float difference of the very floats it stores, so equality is exact.
void expectWellFormedRay(const float* s, uint32_t n, float tFar) {
  for (uint32_t i = 0; i < n; ++i) {
    ASSERT_TRUE(std::isfinite(s[2 * i]) && std::isfinite(s[2 * i + 1])) << "sample " << i;
    EXPECT_GE(s[2 * i + 1], 0.0f);
    float next = i + 1 < n ? s[2 * i + 2] : tFar;
    EXPECT_LE(s[2 * i], next) << "sample " << i;
    EXPECT_EQ(s[2 * i + 1], next - s[2 * i]) << "sample " << i;
  }
}

// Stratified t in float vs the same formula on the device: add, multiply and divide in the same
// order, `precise` forbids contraction; only division may differ (Vulkan allows 2.5 ulp), moving the
// bin fraction by ~3 eps, i.e. t by 3 eps * (t_far - t_near), plus 1 ulp of t itself.
double stratifiedTol(float tn, float tf) { return 4 * kEps * (std::fabs(tn) + std::fabs(tf)); }

class SamplesStratified : public test::GpuTest {};
class SamplesPdf : public test::GpuTest {};

std::vector<std::pair<float, float>> randomBounds(uint32_t n, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> near(0.05f, 3.0f), len(1e-3f, 5.0f);
  std::vector<std::pair<float, float>> out;
  for (uint32_t i = 0; i < n; ++i) {
    float tn = near(gen);
    out.push_back({tn, tn + len(gen)});
  }
  return out;
}

}  // namespace

// ---------------------------------------------------------------- stratified

TEST_F(SamplesStratified, MatchesReferenceJitteredAndCentres) {
  auto bounds = randomBounds(300, 1);
  bounds[17] = {-1, -1};
  bounds[41] = {2.5f, 2.5f};
  for (uint32_t n : {64u, 7u}) {
    for (bool jitter : {true, false}) {
      auto g = runStratified(ctx(), bounds, n, 99, jitter);
      for (uint32_t r = 0; r < bounds.size(); ++r) {
        auto [tn, tf] = bounds[r];
        auto f = ref::stratifiedSamples<float>(tn, tf, n, 99, r, jitter);
        auto d = ref::stratifiedSamples<double>(tn, tf, n, 99, r, jitter);
        double tol = stratifiedTol(tn, tf);
        for (uint32_t i = 0; i < n; ++i) {
          const float* s = &g[2 * (r * n + i)];
          ASSERT_TRUE(test::near(s[0], f[i].t, 0, tol)) << "ray " << r << " sample " << i;
          ASSERT_TRUE(test::near(s[1], f[i].delta, 0, 2 * tol)) << "ray " << r << " sample " << i;
          // The float path itself is a few roundings away from exact arithmetic on the same u.
          ASSERT_TRUE(test::near(s[0], d[i].t, 0, tol)) << "ray " << r << " sample " << i;
          ASSERT_TRUE(test::near(s[1], d[i].delta, 0, 2 * tol)) << "ray " << r << " sample " << i;
        }
      }
    }
  }
}

TEST_F(SamplesStratified, OneSamplePerBinSortedSegmentsTileTheRay) {
  auto bounds = randomBounds(200, 2);
  const uint32_t n = 32;
  for (bool jitter : {true, false}) {
    auto g = runStratified(ctx(), bounds, n, 5, jitter);
    for (uint32_t r = 0; r < bounds.size(); ++r) {
      auto [tn, tf] = bounds[r];
      const float* s = &g[2 * r * n];
      expectWellFormedRay(s, n, tf);
      double len = double(tf) - tn, tol = stratifiedTol(tn, tf);
      double sum = 0;
      for (uint32_t i = 0; i < n; ++i) {
        EXPECT_GE(s[2 * i], tn + len * i / n - tol) << "ray " << r << " sample " << i;
        EXPECT_LE(s[2 * i], tn + len * (i + 1) / n + tol) << "ray " << r << " sample " << i;
        if (!jitter) EXPECT_TRUE(test::near(s[2 * i], tn + len * (i + 0.5) / n, 0, tol));
        sum += s[2 * i + 1];
      }
      // The segments cover [t_0, t_far]; the stretch [t_near, t_0) inside the first bin is nobody's.
      EXPECT_TRUE(test::near(sum + (s[0] - double(tn)), len, 0, n * kEps * tf));
      if (!jitter) EXPECT_TRUE(test::near(sum, len * (1 - 0.5 / n), 0, n * kEps * tf));
    }
  }
}

TEST_F(SamplesStratified, MissAndEmptyRaysGetZeroDeltas) {
  std::vector<std::pair<float, float>> bounds = {{-1, -1}, {2.5f, 2.5f}, {0, 0}, {1, 2}, {3, 1}};
  auto g = runStratified(ctx(), bounds, 16, 3, true);
  float expectedT[] = {0, 2.5f, 0, 0, 3};
  for (uint32_t r : {0u, 1u, 2u, 4u}) {
    for (uint32_t i = 0; i < 16; ++i) {
      EXPECT_EQ(g[2 * (r * 16 + i)], expectedT[r]);
      EXPECT_EQ(g[2 * (r * 16 + i) + 1], 0.0f);
    }
  }
  expectWellFormedRay(&g[2 * 3 * 16], 16, 2.0f);  // the neighbouring hit ray is unaffected
  EXPECT_GT(g[2 * 3 * 16 + 1], 0.0f);
}

TEST_F(SamplesStratified, JitterIsTheReferenceRngBitForBit) {
  // One bin over [0, 1]: t = 0 + (0 + u) / 1 * 1 = u, exact in float, so t exposes rng01 itself.
  std::vector<std::pair<float, float>> bounds(1000, {0.0f, 1.0f});
  auto g = runStratified(ctx(), bounds, 1, 2024, true);
  for (uint32_t r = 0; r < bounds.size(); ++r) {
    ASSERT_EQ(g[2 * r], ref::rng01(2024, r, 0)) << "ray " << r;
    ASSERT_EQ(g[2 * r + 1], 1.0f - g[2 * r]);
  }
}

TEST_F(SamplesStratified, HardInputsStaySortedAndFinite) {
  // Many bins (i + u rounds up to i + 1), bins narrower than one ulp of t, a huge range.
  std::vector<std::pair<float, float>> bounds = {{0.0f, 1e-30f}, {1e6f, 1e6f + 0.25f}, {0.0f, 3e38f}, {0.5f, 0.5000001f}};
  const uint32_t n = 1024;
  auto g = runStratified(ctx(), bounds, n, 11, true);
  for (uint32_t r = 0; r < bounds.size(); ++r) {
    const float* s = &g[2 * r * n];
    expectWellFormedRay(s, n, bounds[r].second);
    for (uint32_t i = 0; i < n; ++i) {
      EXPECT_GE(s[2 * i], bounds[r].first);
      EXPECT_LE(s[2 * i], bounds[r].second);
    }
  }
}

TEST_F(SamplesStratified, EmptyBatchAndUndersizedBuffers) {
  EXPECT_TRUE(runStratified(ctx(), {}, 64, 0, true).empty());
  auto rays = gpu::Buffer::of(ctx(), packRays({{1, 2}, {1, 2}}));
  gpu::Buffer small(ctx(), 2 * 63 * nerf::kSampleBytes);
  nerf::StratifiedSampler sampler(ctx());
  gpu::Recorder rec(ctx());
  rec.begin();
  EXPECT_THROW(sampler.record(rec, {rays, 2}, 64, {0, true}, small), Error);
  EXPECT_THROW(sampler.record(rec, {rays, 3}, 1, {0, true}, small), Error);  // 3 rays, buffer of 2
  rec.end();
}

// ---------------------------------------------------------------- inverse CDF

TEST(SamplesInverseCdf, WorkedExampleOfTheChapter) {
  // Seed §4.10 / exercise C5: CDF (0.05, 0.15, 0.75, 1); u = 0.40 -> 2.0 + 0.25/0.60 * 0.5.
  auto cdf = ref::makeCdf<double>({1, 1.5, 2, 2.5, 3}, {0.05, 0.10, 0.60, 0.25}, 0.0);
  EXPECT_NEAR(ref::invertCdf(cdf, 0.40), 2.208333, 1e-6);
  EXPECT_NEAR(ref::invertCdf(cdf, 0.90), 2.80, 1e-12);
  // Bin boundaries of the CDF map to the bin edges; the ends to the ends.
  EXPECT_NEAR(ref::invertCdf(cdf, 0.05), 1.5, 1e-12);
  EXPECT_NEAR(ref::invertCdf(cdf, 0.75), 2.5, 1e-12);
  EXPECT_EQ(ref::invertCdf(cdf, 0.0), 1.0);
  EXPECT_EQ(ref::invertCdf(cdf, 1.0), 3.0);
  auto cdfF = ref::makeCdf<float>({1, 1.5f, 2, 2.5f, 3}, {0.05f, 0.10f, 0.60f, 0.25f}, 0.0f);
  EXPECT_NEAR(ref::invertCdf(cdfF, 0.40f), 2.208333, 4e-7);  // a few float roundings of values ~2
  EXPECT_NEAR(ref::invertCdf(cdfF, 0.90f), 2.80, 4e-7);
}

TEST(SamplesInverseCdf, PaddingAndFallbackInTheReference) {
  // Padding lifts empty bins: with weights (0, 1) and padding 1 the masses are (1, 2).
  auto cdf = ref::makeCdf<double>({0, 1, 2}, {0, 1}, 1.0);
  EXPECT_NEAR(ref::invertCdf(cdf, 1.0 / 6), 0.5, 1e-12);
  EXPECT_NEAR(ref::invertCdf(cdf, 2.0 / 3), 1.5, 1e-12);
  // A ray's bins: [t_near, t_0] without mass, then the coarse segments with their padded weights.
  auto ray = ref::rayCdf<double>(0.5, 3, {1, 2}, {0.25, 0.75}, 0.0);
  EXPECT_EQ(ray.edges, (std::vector<double>{0.5, 1, 2, 3}));
  EXPECT_EQ(ray.mass, (std::vector<double>{0, 0.25, 0.75}));
  EXPECT_EQ(ref::invertCdf(ray, 0.0), 1.0);  // u = 0 goes to the first bin with mass, not t_near
  // No mass, or coarse segments of no length: every bin weighs its width, uniform over [t_near, t_far].
  for (auto c : {ref::rayCdf<double>(0.5, 3, {1, 2}, {0, 0}, 0.0), ref::rayCdf<double>(0.5, 3, {3, 3}, {1, 1}, 0.0)}) {
    EXPECT_NEAR(c.total(), 2.5, 1e-15);
    for (double u : {0.0, 0.1, 0.5, 0.9, 1.0}) EXPECT_NEAR(ref::invertCdf(c, u), 0.5 + 2.5 * u, 1e-15);
  }
}

TEST_F(SamplesPdf, WorkedExampleOnTheDevice) {
  // C5's bins as coarse samples t = 1, 1.5, 2, 2.5 on a ray ending at 3; deterministic draws
  // u = 0.1, 0.3, 0.5, 0.7, 0.9 placed by the chapter's formula t = e_k + (u - F_{k-1}) / w_k * 0.5.
  PdfCase c{{{1.0f, 3.0f}}, {1, 1.5f, 2, 2.5f}, {0.05f, 0.10f, 0.60f, 0.25f}, 4, 5, 0, false, 0.0f};
  auto g = runPdf(ctx(), c);
  double expected[] = {1, 1.5, 1.5 + 0.05 / 0.10 * 0.5, 2, 2 + 0.15 / 0.6 * 0.5, 2 + 0.35 / 0.6 * 0.5,
                       2 + 0.55 / 0.6 * 0.5, 2.5, 2.5 + 0.15 / 0.25 * 0.5};
  for (int i = 0; i < 9; ++i) EXPECT_TRUE(test::near(g[2 * i], expected[i], 0, 1e-6)) << i;  // float roundings of ~2
  expectWellFormedRay(g.data(), 9, 3.0f);
  auto ref = refPdf<float>(c, 0);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(g[2 * i], ref[i].t) << i;  // same float operations, no division differences here
}

namespace {

// Random rays with stratified coarse samples and random weights, some of them zero.
PdfCase randomCase(uint32_t numRays, uint32_t nc, uint32_t nf, bool jitter, float padding, float wMin, uint32_t seed) {
  PdfCase c;
  c.bounds = randomBounds(numRays, seed);
  c.nCoarse = nc;
  c.nFine = nf;
  c.jitter = jitter;
  c.padding = padding;
  c.seed = seed * 31 + 1;
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> w(wMin, 1.0f);
  for (uint32_t r = 0; r < numRays; ++r) {
    auto s = ref::stratifiedSamples<float>(c.bounds[r].first, c.bounds[r].second, nc, seed, r, true);
    for (uint32_t k = 0; k < nc; ++k) {
      c.coarseT.push_back(s[k].t);
      c.weights.push_back(wMin == 0 && gen() % 3 == 0 ? 0.0f : w(gen));
    }
  }
  return c;
}

}  // namespace

TEST_F(SamplesPdf, RandomWeightsMatchReference) {
  for (bool jitter : {true, false}) {
    for (float padding : {1e-5f, 0.0f}) {
      PdfCase c = randomCase(128, 64, 128, jitter, padding, 0.0f, jitter ? 3 : 4);
      c.bounds[5] = {-1, -1};
      auto g = runPdf(ctx(), c);
      const uint32_t nOut = c.nCoarse + c.nFine;
      for (uint32_t r = 0; r < c.bounds.size(); ++r) {
        auto ref = refPdf<float>(c, r);
        float tf = c.bounds[r].second;
        // The CDF sums and u * total are adds and multiplies, correctly rounded on every Vulkan
        // device, so the bins match; only the division (2.5 ulp allowed) moves t within its bin.
        double tol = 8 * kEps * std::fabs(tf);
        const float* s = &g[2 * r * nOut];
        for (uint32_t i = 0; i < nOut; ++i) {
          ASSERT_TRUE(test::near(s[2 * i], ref[i].t, 0, tol)) << "ray " << r << " sample " << i;
          ASSERT_TRUE(test::near(s[2 * i + 1], ref[i].delta, 0, 2 * tol)) << "ray " << r << " sample " << i;
        }
        if (r != 5) expectWellFormedRay(s, nOut, tf);
      }
    }
  }
}

TEST_F(SamplesPdf, FloatPathCloseToExactArithmetic) {
  // Weights in [0.05, 1]: every bin has mass, the inverse CDF is continuous and the float result is
  // within the error of the prefix sums: each cumulative mass carries at most (Nc + 2) eps * total,
  // which moves a sample by that over its bin's mass, times the bin width.
  PdfCase c = randomCase(64, 64, 128, true, 1e-5f, 0.05f, 8);
  auto g = runPdf(ctx(), c);
  const uint32_t nOut = c.nCoarse + c.nFine;
  for (uint32_t r = 0; r < c.bounds.size(); ++r) {
    auto exact = refPdf<double>(c, r);
    double total = 0, worst = 0;
    for (uint32_t k = 0; k < c.nCoarse; ++k) {
      double lo = c.coarseT[r * c.nCoarse + k], hi = k + 1 < c.nCoarse ? c.coarseT[r * c.nCoarse + k + 1] : c.bounds[r].second;
      double m = c.weights[r * c.nCoarse + k] + c.padding;
      total += m;
      worst = std::max(worst, (hi - lo) / m);
    }
    double tol = 4 * kEps * c.bounds[r].second + (c.nCoarse + 2) * kEps * total * worst;
    for (uint32_t i = 0; i < nOut; ++i)
      ASSERT_TRUE(test::near(g[2 * (r * nOut + i)], exact[i].t, 0, tol)) << "ray " << r << " sample " << i;
  }
}

TEST_F(SamplesPdf, MergedKeepsEveryCoarseSampleAndPlacesFineOnesInRange) {
  PdfCase c = randomCase(64, 16, 48, true, 1e-5f, 0.0f, 12);
  auto g = runPdf(ctx(), c);
  const uint32_t nOut = 64;
  for (uint32_t r = 0; r < c.bounds.size(); ++r) {
    std::vector<float> ts;
    for (uint32_t i = 0; i < nOut; ++i) ts.push_back(g[2 * (r * nOut + i)]);
    std::vector<float> coarse = slice<float>(c.coarseT, r * c.nCoarse, c.nCoarse);
    std::vector<float> fine;
    std::set_difference(ts.begin(), ts.end(), coarse.begin(), coarse.end(), std::back_inserter(fine));
    EXPECT_EQ(fine.size(), c.nFine) << "ray " << r << ": coarse samples missing from the merge";
    EXPECT_GE(fine.front(), coarse.front());
    EXPECT_LE(fine.back(), c.bounds[r].second);
  }
}

TEST_F(SamplesPdf, NoUsableWeightsFallBackToUniform) {
  // Per ray: all zero, NaN, +Inf, or so small they sum below kMinMass; padding 0 throughout.
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const uint32_t nc = 8, nf = 16;
  PdfCase c;
  c.nCoarse = nc;
  c.nFine = nf;
  float bad[] = {0.0f, nan, inf, 1e-38f};
  for (int r = 0; r < 4; ++r) {
    c.bounds.push_back({1.0f + r, 4.0f + r});
    auto s = ref::stratifiedSamples<float>(1.0f + r, 4.0f + r, nc, 0, r, true);
    for (uint32_t k = 0; k < nc; ++k) {
      c.coarseT.push_back(s[k].t);
      c.weights.push_back(k == 3 || r == 0 ? bad[r] : 0.0f);
    }
  }
  auto g = runPdf(ctx(), c);
  for (uint32_t r = 0; r < 4; ++r) {
    const float* s = &g[2 * r * (nc + nf)];
    expectWellFormedRay(s, nc + nf, c.bounds[r].second);
    std::vector<float> ts;
    for (uint32_t i = 0; i < nc + nf; ++i) ts.push_back(s[2 * i]);
    std::vector<float> coarse = slice<float>(c.coarseT, r * nc, nc), fine;
    std::set_difference(ts.begin(), ts.end(), coarse.begin(), coarse.end(), std::back_inserter(fine));
    ASSERT_EQ(fine.size(), nf) << "ray " << r;
    for (uint32_t j = 0; j < nf; ++j)  // uniform over [t_near, t_far]: t_near + (j + 0.5) / nf * 3
      EXPECT_TRUE(test::near(fine[j], c.bounds[r].first + 3.0 * (j + 0.5) / nf, 0, 4 * kEps * 8)) << "ray " << r;
  }
}

TEST_F(SamplesPdf, OneBinHoldsAllTheMass) {
  const uint32_t nc = 32, nf = 64, hot = 17;
  PdfCase c = randomCase(16, nc, nf, false, 0.0f, 0.0f, 21);
  for (uint32_t r = 0; r < 16; ++r)
    for (uint32_t k = 0; k < nc; ++k) c.weights[r * nc + k] = k == hot ? 0.7f : 0.0f;
  auto g = runPdf(ctx(), c);
  for (uint32_t r = 0; r < 16; ++r) {
    const float* s = &g[2 * r * (nc + nf)];
    expectWellFormedRay(s, nc + nf, c.bounds[r].second);
    double lo = c.coarseT[r * nc + hot], hi = c.coarseT[r * nc + hot + 1];
    // Output: coarse 0..17, the 64 fine samples evenly inside bin 17, coarse 18..31.
    for (uint32_t j = 0; j < nf; ++j) {
      float t = s[2 * (hot + 1 + j)];
      EXPECT_GE(t, lo);
      EXPECT_LE(t, hi);
      EXPECT_TRUE(test::near(t, lo + (hi - lo) * (j + 0.5) / nf, 0, 4 * kEps * c.bounds[r].second));
    }
    EXPECT_EQ(s[2 * (hot + 1 + nf)], float(hi));
  }
}

TEST_F(SamplesPdf, ZeroWidthBins) {
  // Coarse t's 1, 1, 2, 2 on [1, 3]: bins [1,1], [1,2], [2,2], [2,3]. Mass on the two points puts
  // every fine sample exactly on them; a ray whose coarse samples all sit at t_far has bins of no
  // length and falls back to uniform over [t_near, t_far].
  PdfCase c{{{1.0f, 3.0f}, {1.0f, 3.0f}}, {1, 1, 2, 2, 3, 3, 3, 3}, {0.5f, 0, 0.5f, 0, 0.3f, 0.3f, 0.3f, 0.1f}, 4, 8, 9, true, 0.0f};
  auto g = runPdf(ctx(), c);
  const float* a = g.data();
  expectWellFormedRay(a, 12, 3.0f);
  int atOne = 0, atTwo = 0;
  for (int i = 0; i < 12; ++i) {
    atOne += a[2 * i] == 1.0f;
    atTwo += a[2 * i] == 2.0f;
  }
  EXPECT_EQ(atOne, 2 + 4);  // two coarse, half of the eight fine draws
  EXPECT_EQ(atTwo, 2 + 4);
  const float* b = g.data() + 24;
  expectWellFormedRay(b, 12, 3.0f);
  for (int j = 0; j < 8; ++j) {  // fine draws come first, below the coarse samples at 3
    float u = (j + ref::rng01(9, 1, j)) / 8.0f;
    EXPECT_TRUE(test::near(b[2 * j], 1.0 + 2.0 * u, 0, 4 * kEps * 3)) << j;
  }
  for (int i = 8; i < 12; ++i) EXPECT_EQ(b[2 * i], 3.0f);
}

TEST_F(SamplesPdf, DrawOnACdfStepBeforeAnEmptyBinStaysInTheFullBin) {
  // Masses (0.5, 0, 0.5) on [0,1], [1,2], [2,3]: u = 0.5 equals F_0 = F_1, and the chapter's rule
  // F_{k-1} < u <= F_k picks bin 0, so t = 1 (its end), not 2 (the start of the next full bin).
  auto cdf = ref::makeCdf<double>({0, 1, 2, 3}, {0.5, 0, 0.5}, 0.0);
  EXPECT_EQ(ref::invertCdf(cdf, 0.5), 1.0);
  EXPECT_EQ(ref::invertCdf(cdf, std::nextafter(0.5, 1.0)), 2.0);
  // One deterministic draw is u = (0 + 0.5) / 1 exactly.
  PdfCase c{{{0.0f, 3.0f}}, {0, 1, 2}, {0.5f, 0, 0.5f}, 3, 1, 0, false, 0.0f};
  auto g = runPdf(ctx(), c);
  float expected[] = {0, 1, 1, 2};
  for (int i = 0; i < 4; ++i) EXPECT_EQ(g[2 * i], expected[i]) << i;
}

TEST_F(SamplesPdf, FractionOfDrawsPerBinApproachesTheWeights) {
  // 1024 rays x 4 jittered draws on C5's bins. With 4 stratified draws per ray only the draws whose
  // stratum straddles a CDF boundary are random, so the fractions' standard deviation is below
  // 0.004: +-0.02 is five sigma.
  const uint32_t numRays = 1024, nf = 4;
  PdfCase c;
  c.nCoarse = 4;
  c.nFine = nf;
  c.jitter = true;
  c.seed = 77;
  for (uint32_t r = 0; r < numRays; ++r) {
    c.bounds.push_back({1.0f, 3.0f});
    c.coarseT.insert(c.coarseT.end(), {1, 1.5f, 2, 2.5f});
    c.weights.insert(c.weights.end(), {0.05f, 0.10f, 0.60f, 0.25f});
  }
  auto g = runPdf(ctx(), c);
  double edges[] = {1, 1.5, 2, 2.5, 3}, weights[] = {0.05, 0.10, 0.60, 0.25};
  double count[4] = {}, fracSum[4] = {};
  for (uint32_t r = 0; r < numRays; ++r) {
    const float* s = &g[2 * r * 8];
    expectWellFormedRay(s, 8, 3.0f);
    std::vector<float> ts, coarse = {1, 1.5f, 2, 2.5f}, fine;
    for (int i = 0; i < 8; ++i) ts.push_back(s[2 * i]);
    std::set_difference(ts.begin(), ts.end(), coarse.begin(), coarse.end(), std::back_inserter(fine));
    for (float t : fine)
      for (int k = 0; k < 4; ++k)
        if (t >= edges[k] && t < edges[k + 1]) {
          count[k]++;
          fracSum[k] += (t - edges[k]) / (edges[k + 1] - edges[k]);
        }
  }
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(count[k] / (numRays * nf), weights[k], 0.02) << "bin " << k;
    EXPECT_NEAR(fracSum[k] / count[k], 0.5, 0.05) << "bin " << k;  // uniform within the bin
  }
}

TEST_F(SamplesPdf, EmptyRaysAndDegenerateCounts) {
  // Misses and empty rays: all nCoarse + nFine samples (max(t_near, 0), 0).
  PdfCase miss{{{-1, -1}, {2.5f, 2.5f}}, {0, 0, 0, 2.5f, 2.5f, 2.5f}, {1, 1, 1, 1, 1, 1}, 3, 5, 1, true, 1e-5f};
  auto g = runPdf(ctx(), miss);
  for (int i = 0; i < 16; ++i) {
    EXPECT_EQ(g[2 * i], i < 8 ? 0.0f : 2.5f);
    EXPECT_EQ(g[2 * i + 1], 0.0f);
  }
  // No fine samples: the coarse samples come back with their deltas. No coarse samples: uniform.
  for (auto [nc, nf] : {std::pair{16u, 0u}, std::pair{0u, 12u}}) {
    PdfCase c = randomCase(8, nc, nf, true, 1e-5f, 0.0f, 30 + nc);
    auto out = runPdf(ctx(), c);
    for (uint32_t r = 0; r < 8; ++r) {
      auto ref = refPdf<float>(c, r);
      for (uint32_t i = 0; i < nc + nf; ++i) {
        EXPECT_TRUE(test::near(out[2 * (r * (nc + nf) + i)], ref[i].t, 0, 8 * kEps * c.bounds[r].second));
        EXPECT_TRUE(test::near(out[2 * (r * (nc + nf) + i) + 1], ref[i].delta, 0, 16 * kEps * c.bounds[r].second));
      }
      expectWellFormedRay(&out[2 * r * (nc + nf)], nc + nf, c.bounds[r].second);
    }
  }
}

TEST_F(SamplesPdf, RejectsUndersizedBuffersAndBadPadding) {
  auto rays = gpu::Buffer::of(ctx(), packRays({{1, 2}, {1, 2}}));
  gpu::Buffer coarse(ctx(), 2 * 64 * nerf::kSampleBytes), weights(ctx(), 2 * 64 * 4),
      merged(ctx(), 2 * 192 * nerf::kSampleBytes);
  nerf::PdfSampler sampler(ctx());
  gpu::Recorder rec(ctx());
  rec.begin();
  EXPECT_THROW(sampler.record(rec, {rays, 2}, {coarse, weights, 64}, {129, {0, true}, 0}, merged), Error);
  EXPECT_THROW(sampler.record(rec, {rays, 2}, {coarse, weights, 65}, {127, {0, true}, 0}, merged), Error);
  EXPECT_THROW(sampler.record(rec, {rays, 2}, {coarse, weights, 64}, {128, {0, true}, -1e-5f}, merged), Error);
  EXPECT_THROW(sampler.record(rec, {rays, 2}, {coarse, weights, 64}, {128, {0, true}, std::nanf("")}, merged), Error);
  rec.end();
}

// The proposal estimator's kernels, proposal_sample.comp and proposal_interlevel.comp, against the
// CPU reference (tests/reference/sampling/proposal.h), and the reference's gradient against finite
// differences of its loss in double precision.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <tuple>
#include <vector>

#include "gpu/dispatch/recorder.h"
#include "gpu/memory/buffer.h"
#include "nerf/sampling/interlevel_loss.h"
#include "nerf/sampling/packed_points.h"
#include "nerf/sampling/proposal_sampler.h"
#include "reference/sampling/proposal.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

// One ray's candidates as the march leaves them: sorted intervals (t, delta) with gaps between
// some of them, and a proposal density at each.
struct Ray {
  std::vector<double> candidates, sigma;
};

Ray randomRay(std::mt19937& rng, size_t k, bool gaps = true) {
  std::uniform_real_distribution<double> step(0.01, 0.08), gap(0.0, 0.5), u01(0.0, 1.0);
  Ray r;
  double t = 0.5 + u01(rng);
  for (size_t i = 0; i < k; ++i) {
    double d = step(rng);
    r.candidates.insert(r.candidates.end(), {t, d});
    t += d + (gaps && u01(rng) < 0.2 ? gap(rng) : 0.0);
    // Mostly thin, with a few dense stretches: a surface, some fog.
    r.sigma.push_back(u01(rng) < 0.15 ? 5.0 + 40.0 * u01(rng) : 0.5 * u01(rng));
  }
  return r;
}

template <class T> std::vector<T> as(const std::vector<double>& v) { return std::vector<T>(v.begin(), v.end()); }

double occupiedLength(const std::vector<double>& pairs) {
  double sum = 0;
  for (size_t i = 1; i < pairs.size(); i += 2) sum += std::max(pairs[i], 0.0);
  return sum;
}

// The packed layout of several rays: offsets and the concatenated entries; a ray's densities go
// to the w of a field's vec4 (fieldRows), its field weights stay floats (values).
struct Packed {
  std::vector<uint32_t> offsets{0};
  std::vector<float> pairs, values, fieldRows;
  void add(const std::vector<double>& p, const std::vector<double>& v) {
    offsets.push_back(offsets.back() + uint32_t(p.size() / 2));
    for (double x : p) pairs.push_back(float(x));
    for (double x : v) {
      values.push_back(float(x));
      fieldRows.insert(fieldRows.end(), {0.5f, 0.5f, 0.5f, float(x)});
    }
  }
};

// Buffers may not be empty: pad what a case leaves empty.
template <class T> std::vector<T> padded(std::vector<T> v) {
  v.resize(std::max<size_t>(v.size(), 4));
  return v;
}

class Proposal : public test::GpuTest {
 protected:
  // What the sampler writes for `rays` at draws.samplesPerRay a ray and `capacity` samples.
  struct Sampled {
    std::vector<uint32_t> offsets, sampleRay, totals;
    std::vector<float> samples;  // (t, delta) pairs, offsets.back() of them
  };
  Sampled sample(const std::vector<Ray>& rays, nerf::ProposalSampler::Draws draws, uint32_t capacity = 1u << 16) {
    Packed c;
    for (const Ray& r : rays) c.add(r.candidates, r.sigma);
    const uint32_t numRays = uint32_t(rays.size());
    auto candOff = gpu::Buffer::of(ctx(), c.offsets), cand = gpu::Buffer::of(ctx(), padded(c.pairs)),
         field = gpu::Buffer::of(ctx(), padded(c.fieldRows));
    gpu::Buffer offsets(ctx(), (numRays + 1) * 4), totals(ctx(), nerf::PackedLayout::kTotalsBytes),
        samples(ctx(), std::max<VkDeviceSize>(capacity * nerf::kSampleBytes, 16)),
        sampleRay(ctx(), std::max<VkDeviceSize>(capacity * 4, 16));
    nerf::ProposalSampler sampler(ctx(), numRays);
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      sampler.record(rec, numRays, {candOff, cand, field}, draws, capacity, {offsets, samples, sampleRay, totals});
    });
    Sampled s;
    s.offsets = offsets.download<uint32_t>(numRays + 1);
    s.totals = totals.download<uint32_t>(4);
    s.samples = samples.download<float>(size_t(s.offsets.back()) * 2);
    s.sampleRay = sampleRay.download<uint32_t>(s.offsets.back());
    return s;
  }

  struct InterlevelOut {
    std::vector<float> dWeights, dSigma, loss;
  };
  InterlevelOut interlevel(const std::vector<Ray>& rays, const std::vector<std::vector<double>>& samples,
                           const std::vector<std::vector<double>>& fieldWeights, nerf::InterlevelLoss::Terms terms) {
    Packed c, s;
    for (size_t r = 0; r < rays.size(); ++r) {
      c.add(rays[r].candidates, rays[r].sigma);
      s.add(samples[r], fieldWeights[r]);
    }
    auto candOff = gpu::Buffer::of(ctx(), c.offsets), cand = gpu::Buffer::of(ctx(), padded(c.pairs)),
         field = gpu::Buffer::of(ctx(), padded(c.fieldRows)), sampOff = gpu::Buffer::of(ctx(), s.offsets),
         samp = gpu::Buffer::of(ctx(), padded(s.pairs)), weights = gpu::Buffer::of(ctx(), padded(s.values));
    const size_t k = c.values.size();
    gpu::Buffer dW(ctx(), std::max<VkDeviceSize>(k * 4, 16)), dField(ctx(), std::max<VkDeviceSize>(k * 16, 16)),
        loss(ctx(), std::max<VkDeviceSize>(rays.size() * 4, 16));
    nerf::InterlevelLoss kernel(ctx());
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      // The interlevel loss reads only the offsets and samples of a packed batch.
      kernel.record(rec, uint32_t(rays.size()), {candOff, cand, field}, {sampOff, samp, samp, samp}, weights, terms,
                    {dW, dField, loss});
    });
    std::vector<float> rows = dField.download<float>(4 * k), dSigma(k);
    for (size_t i = 0; i < k; ++i) {
      EXPECT_EQ(rows[4 * i] + rows[4 * i + 1] + rows[4 * i + 2], 0.0f) << "the colour gets no gradient";
      dSigma[i] = rows[4 * i + 3];
    }
    return {dW.download<float>(k), dSigma, loss.download<float>(rays.size())};
  }
};

// ---- The reference ----

TEST(ProposalReference, SamplesTileTheOccupiedLengthWithEqualMass) {
  std::mt19937 rng(3);
  Ray r = randomRay(rng, 40);
  const uint32_t n = 16;
  for (double shift : {0.0, -0.5, 0.37}) {
    std::vector<double> s = ref::proposalSamples<double>(r.candidates, r.sigma, n, 0.0, shift);
    double tiled = occupiedLength(s);
    EXPECT_NEAR(tiled, occupiedLength(r.candidates), 1e-12);
    // Without padding the interior bins each hold 1/n of the weight, the first and last what the
    // shift leaves them: measured by a fine sum of the weight density over each bin.
    std::vector<double> w = ref::proposalWeights<double>(r.candidates, r.sigma);
    double total = 0;
    for (double x : w) total += x;
    std::vector<double> u = ref::occupiedStarts<double>(r.candidates);
    double e0 = 0;
    for (uint32_t j = 0; j < n; ++j) {
      double e1 = e0 + s[2 * j + 1], mass = 0;
      for (size_t i = 0; i < w.size(); ++i) {
        double overlap = std::min(e1, u[i + 1]) - std::max(e0, u[i]);
        if (overlap > 0) mass += w[i] * overlap / (u[i + 1] - u[i]);
      }
      double expected = (j == 0 ? (1 + shift) : j + 1 == n ? (1 - shift) : 1.0) / n * total;
      EXPECT_NEAR(mass, expected, 1e-9 * total) << "bin " << j << " shift " << shift;
      // The midpoint lies inside a candidate, in t.
      EXPECT_GE(s[2 * j], r.candidates[0]);
      e0 = e1;
    }
  }
}

TEST(ProposalReference, SamplesCrowdIntoTheOpaqueCandidate) {
  // 64 equal candidates of thin fog and one opaque one: a proposal that saw the surface puts most
  // of a ray's samples inside it.
  Ray r;
  for (int i = 0; i < 64; ++i) {
    r.candidates.insert(r.candidates.end(), {1.0 + 0.05 * i, 0.05});
    r.sigma.push_back(i == 40 ? 200.0 : 0.01);
  }
  std::vector<double> s = ref::proposalSamples<double>(r.candidates, r.sigma, 16, 0.01, 0.0);
  int inside = 0;
  for (int j = 0; j < 16; ++j) inside += s[2 * j] >= 3.0 && s[2 * j] <= 3.05;
  EXPECT_GE(inside, 13);
}

TEST(ProposalReference, InterlevelLossIsZeroWhenTheProposalIsTheField) {
  // The field's samples are the candidates and its weights the proposal's own: every bound is met.
  std::mt19937 rng(5);
  Ray r = randomRay(rng, 30);
  std::vector<double> w = ref::proposalWeights<double>(r.candidates, r.sigma);
  auto res = ref::interlevelLoss<double>(r.candidates, r.sigma, r.candidates, w);
  EXPECT_EQ(res.loss, 0.0);
  for (double g : res.dSigma) EXPECT_EQ(g, 0.0);
  // Halving the proposal's densities lowers its weights at the surface: the loss turns positive.
  std::vector<double> half = r.sigma;
  for (double& x : half) x *= 0.5;
  EXPECT_GT(ref::interlevelLoss<double>(r.candidates, half, r.candidates, w).loss, 0.0);
}

TEST(ProposalReference, InterlevelSigmaGradientMatchesFiniteDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int trial = 0; trial < 4; ++trial) {
    Ray r = randomRay(rng, 24 + 8 * trial);
    std::vector<double> samples = ref::proposalSamples<double>(r.candidates, r.sigma, 12, 0.01, 0.1 * trial);
    // Field weights above the bounds where the proposal is thin, so that most terms are active.
    std::vector<double> fw(12);
    for (double& w : fw) w = 0.02 + 0.2 * u01(rng);
    auto res = ref::interlevelLoss<double>(r.candidates, r.sigma, samples, fw, 0.7);
    for (size_t k = 0; k < r.sigma.size(); ++k) {
      const double h = 1e-6 * std::max(1.0, r.sigma[k]);
      std::vector<double> plus = r.sigma, minus = r.sigma;
      plus[k] += h;
      minus[k] -= h;
      double fd = (ref::interlevelLoss<double>(r.candidates, plus, samples, fw, 0.7).loss -
                   ref::interlevelLoss<double>(r.candidates, minus, samples, fw, 0.7).loss) / (2 * h);
      // Central differences in double: truncation O(h^2) and rounding ~1e-16 / h, far below this.
      EXPECT_NEAR(res.dSigma[k], fd, 1e-6 + 1e-5 * std::abs(fd)) << "trial " << trial << " candidate " << k;
    }
  }
}

// ---- The kernels against the reference ----

// Tolerances. The kernels compute in float what the reference does in double, but through the
// composite's alpha (a series below x = 0.5, where the reference takes expm1): weights agree to a
// few float ulps. An edge is the inverse CDF of a mass that sums candidates' weights, so its error
// is the sum's rounding (k ulps of the total) over the smallest mass per length (the padding's
// 1% of the total spread over the occupied length U): about 1e-4 U for the 60-candidate rays here.
// Midpoints inherit it; a t is a candidate's start plus a distance in u, so the bound is absolute.
constexpr double kEdgeTolerance = 2e-4;

TEST_F(Proposal, SamplesMatchReference) {
  std::mt19937 rng(7);
  std::vector<Ray> rays;
  for (int i = 0; i < 6; ++i) rays.push_back(randomRay(rng, 10 + 10 * i, i % 2 == 0));
  rays.push_back({});                                   // no candidates
  Ray zero = randomRay(rng, 20);
  for (double& s : zero.sigma) s = 0;                   // no weight: the padding alone
  rays.push_back(zero);
  Ray hard = randomRay(rng, 20);
  hard.sigma[3] = std::numeric_limits<double>::infinity();
  hard.sigma[7] = std::numeric_limits<double>::quiet_NaN();
  hard.sigma[9] = -4.0;
  rays.push_back(hard);
  rays.push_back(randomRay(rng, 3));                    // fewer candidates than samples
  // Annealed (0.4) the masses pass through pow, a few float ulps more per mass: within the same bound.
  for (uint32_t n : {16u, 5u}) {
    for (auto [jitter, anneal, span] : {std::tuple{false, 1.0f, 1u}, {true, 1.0f, 1u}, {true, 0.4f, 1u}, {false, 1.0f, 4u}}) {
      Sampled got = sample(rays, {n, {9, jitter}, 0.01f, anneal, span});
      // A ray with candidates gets n samples, at most its candidates' march steps; the one without
      // none; the totals hold the sum.
      EXPECT_EQ(got.totals[0], got.offsets.back());
      for (size_t r = 0; r < rays.size(); ++r) {
        const uint32_t first = got.offsets[r], count = got.offsets[r + 1] - first;
        ASSERT_EQ(count, ref::proposalCount(rays[r].sigma.size(), n, span)) << "ray " << r << ", n " << n << ", span " << span;
        double shift = ref::proposalShift<double>(9, uint32_t(r), jitter);
        std::vector<double> want =
            ref::proposalSamples<double>(rays[r].candidates, rays[r].sigma, count, 0.01, shift, anneal);
        double scale = std::max(occupiedLength(rays[r].candidates), 1.0);
        for (uint32_t j = 0; j < count; ++j) {
          const uint32_t at = first + j;
          EXPECT_NEAR(got.samples[2 * at], want[2 * j], kEdgeTolerance * scale) << "ray " << r << " sample " << j;
          EXPECT_NEAR(got.samples[2 * at + 1], want[2 * j + 1], kEdgeTolerance * scale) << "ray " << r << " sample " << j;
          EXPECT_TRUE(std::isfinite(got.samples[2 * at]) && std::isfinite(got.samples[2 * at + 1]));
          EXPECT_EQ(got.sampleRay[at], r);
        }
      }
    }
  }
}

TEST_F(Proposal, AllZeroWeightsWithoutPaddingSampleByLength) {
  // Masses that sum to nothing fall back to each candidate's length: evenly spread samples.
  Ray r;
  for (int i = 0; i < 10; ++i) {
    r.candidates.insert(r.candidates.end(), {1.0 + 0.2 * i, 0.1});  // gaps of 0.1 between
    r.sigma.push_back(0.0);
  }
  std::vector<float> got = sample({r}, {4, {0, false}, 0.0f}).samples;
  ASSERT_EQ(got.size(), 8u);
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR(got[2 * j + 1], 0.25, 1e-6) << j;  // a quarter of the occupied length
    // The midpoint in u, back in t: candidate c = floor(mid / 0.1) starts at 1 + 0.2 c.
    double mid = 0.125 + 0.25 * j;
    int c = int(mid / 0.1);
    EXPECT_NEAR(got[2 * j], 1.0 + 0.2 * c + (mid - 0.1 * c), 1e-5) << j;
  }
}

TEST_F(Proposal, AnnealedToZeroTheWeightsAreIgnored) {
  // At anneal 0 (training's first step) a ray's samples spread by length whatever its proposal
  // says, as without weights: one opaque candidate among faint ones draws no more than its length.
  Ray r;
  for (int i = 0; i < 10; ++i) {
    r.candidates.insert(r.candidates.end(), {1.0 + 0.2 * i, 0.1});
    r.sigma.push_back(i == 6 ? 500.0 : 0.5);
  }
  std::vector<float> annealed = sample({r}, {4, {0, false}, 0.01f, 0.0f}).samples;
  std::vector<float> weighted = sample({r}, {4, {0, false}, 0.01f, 1.0f}).samples;
  ASSERT_EQ(annealed.size(), 8u);
  for (int j = 0; j < 4; ++j) EXPECT_NEAR(annealed[2 * j + 1], 0.25, 1e-5) << j;
  // Weighted, the opaque candidate (occupied length [0.6, 0.7]) holds the middle bins.
  EXPECT_LT(weighted[3], 0.1);
  EXPECT_LT(weighted[5], 0.1);
}

TEST_F(Proposal, CapacityCutsTheLastRaysShort) {
  // Three rays of candidates at 8 samples each into a capacity of 20: the offsets stop at 20, the
  // third ray gets the 4 left, spread over its whole occupied length.
  std::mt19937 rng(17);
  std::vector<Ray> rays{randomRay(rng, 12), randomRay(rng, 12), randomRay(rng, 12)};
  Sampled got = sample(rays, {8, {0, false}, 0.01f}, 20);
  EXPECT_EQ(got.offsets, (std::vector<uint32_t>{0, 8, 16, 20}));
  EXPECT_EQ(got.totals[0], 20u);
  double tiled = 0;
  for (uint32_t i = 16; i < 20; ++i) tiled += got.samples[2 * i + 1];
  EXPECT_NEAR(tiled, occupiedLength(rays[2].candidates), 1e-5);
}

TEST_F(Proposal, InterlevelMatchesReference) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<Ray> rays;
  std::vector<std::vector<double>> samples, weights;
  for (int i = 0; i < 8; ++i) {
    Ray r = i == 5 ? Ray{} : randomRay(rng, 8 + 7 * i, i % 3 != 0);
    uint32_t n = i == 6 ? 0 : 4 + 3 * i;
    samples.push_back(ref::proposalSamples<double>(r.candidates, r.sigma, n, 0.01, 0.2));
    std::vector<double> fw(n);
    for (double& w : fw) w = u01(rng) < 0.5 ? 0.3 * u01(rng) : 0.0;
    if (i == 7 && n > 2) fw[1] = std::numeric_limits<double>::quiet_NaN();  // clamped to 0
    weights.push_back(fw);
    rays.push_back(r);
  }
  rays[4].sigma[2] = std::numeric_limits<double>::infinity();
  const double lossWeight = 0.5;
  InterlevelOut got = interlevel(rays, samples, weights, {float(lossWeight), 1e-7f});
  size_t at = 0;
  for (size_t r = 0; r < rays.size(); ++r) {
    auto want = ref::interlevelLoss<double>(rays[r].candidates, rays[r].sigma, samples[r], weights[r], lossWeight);
    // Float sums of a few dozen terms, each divided by w + 1e-7: a relative 1e-4 covers their
    // rounding; the absolute part covers terms whose w is itself near float's resolution.
    EXPECT_NEAR(got.loss[r], want.loss, 1e-6 + 1e-4 * std::abs(want.loss)) << "ray " << r;
    for (size_t k = 0; k < rays[r].sigma.size(); ++k, ++at) {
      EXPECT_NEAR(got.dWeights[at], want.dWeights[k], 1e-5 + 1e-4 * std::abs(want.dWeights[k])) << r << "/" << k;
      EXPECT_NEAR(got.dSigma[at], want.dSigma[k], 1e-6 + 1e-4 * std::abs(want.dSigma[k])) << r << "/" << k;
      EXPECT_TRUE(std::isfinite(got.dSigma[at]));
    }
  }
}

// With FieldInputs the sampler writes each sample's position and direction as it places it, in place
// of a pass of PackedSamplePoints over its batch: the same bits as that pass makes from the same
// samples (both map through sampling/box_position.glsl), for rays with candidates, without any
// (no samples, nothing written) and with no occupied length (every sample at t = 0); the rows past
// the batch keep their sentinel. The points themselves are PackedSamplePoints' (tested against the
// reference in its own tests); bit equality is what lets the render drop that pass unchanged.
TEST_F(Proposal, FieldInputsAreTheMarchPointsOfItsSamples) {
  std::mt19937 rng(11);
  std::vector<Ray> rays;
  for (int i = 0; i < 5; ++i) rays.push_back(randomRay(rng, 6 + 9 * i));
  rays.push_back({});
  Ray flat = randomRay(rng, 4);
  for (size_t i = 1; i < flat.candidates.size(); i += 2) flat.candidates[i] = 0.0;  // no occupied length
  rays.push_back(flat);
  const uint32_t numRays = uint32_t(rays.size()), capacity = 512, n = 12;
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<float> rayData;
  for (uint32_t r = 0; r < numRays; ++r) {
    float d[3] = {u(rng), u(rng), 0.5f + u(rng) * 0.2f};
    const float len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    rayData.insert(rayData.end(), {u(rng), u(rng), -3.0f + u(rng), 0.0f, d[0] / len, d[1] / len, d[2] / len, 10.0f});
  }
  const Aabb box{{-1.5f, -2.0f, -0.5f}, {1.0f, 2.5f, 3.0f}};
  Packed c;
  for (const Ray& r : rays) c.add(r.candidates, r.sigma);
  auto candOff = gpu::Buffer::of(ctx(), c.offsets), cand = gpu::Buffer::of(ctx(), padded(c.pairs)),
       field = gpu::Buffer::of(ctx(), padded(c.fieldRows)), rayBuf = gpu::Buffer::of(ctx(), rayData);
  gpu::Buffer offsets(ctx(), (numRays + 1) * 4), totals(ctx(), nerf::PackedLayout::kTotalsBytes),
      samples(ctx(), capacity * nerf::kSampleBytes), sampleRay(ctx(), capacity * 4);
  const std::vector<float> sentinel(size_t(capacity) * 4, -7.0f);
  auto positions = gpu::Buffer::of(ctx(), sentinel), directions = gpu::Buffer::of(ctx(), sentinel),
       wantPositions = gpu::Buffer::of(ctx(), sentinel), wantDirections = gpu::Buffer::of(ctx(), sentinel);
  nerf::ProposalSampler sampler(ctx(), numRays);
  nerf::PackedSamplePoints points(ctx());
  const nerf::PackedSamples batch{offsets, samples, sampleRay, totals};
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    sampler.record(rec, numRays, {candOff, cand, field}, {n, {3, true}}, capacity, batch,
                   nerf::ProposalSampler::FieldInputs{rayBuf, box, {positions, directions}});
    points.record(rec, capacity, rayBuf, batch, box, {wantPositions, wantDirections});
  });
  const uint32_t total = offsets.download<uint32_t>(numRays + 1).back();
  ASSERT_GT(total, 0u);
  ASSERT_LT(total, capacity);
  const std::vector<float> gotP = positions.download<float>(size_t(capacity) * 4),
                           gotD = directions.download<float>(size_t(capacity) * 4),
                           wantP = wantPositions.download<float>(size_t(capacity) * 4),
                           wantD = wantDirections.download<float>(size_t(capacity) * 4);
  for (size_t i = 0; i < size_t(capacity) * 4; ++i) {
    ASSERT_EQ(gotP[i], wantP[i]) << "position float " << i;
    ASSERT_EQ(gotD[i], wantD[i]) << "direction float " << i;
    if (i >= size_t(total) * 4) ASSERT_EQ(gotP[i], -7.0f) << "past the batch, float " << i;
  }
}

TEST_F(Proposal, BadSettingsAreErrors) {
  Ray r;
  r.candidates = {1.0, 0.1};
  r.sigma = {1.0};
  EXPECT_THROW(sample({r}, {4, {0, false}, 1.5f}), Error);
  EXPECT_THROW(sample({r}, {4, {0, false}, -0.1f}), Error);
  EXPECT_THROW(sample({r}, {0, {0, false}, 0.01f}), Error);
  EXPECT_THROW(sample({r}, {4, {0, false}, 0.01f, 1.5f}), Error);
  EXPECT_THROW(sample({r}, {4, {0, false}, 0.01f, std::nanf("")}), Error);
  std::vector<std::vector<double>> s{{1.0, 0.1}}, w{{0.5}};
  EXPECT_THROW(interlevel({r}, s, w, {-1.0f, 1e-7f}), Error);
  EXPECT_THROW(interlevel({r}, s, w, {1.0f, 0.0f}), Error);
}

}  // namespace

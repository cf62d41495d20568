// sample_points.comp and encode_frequency.comp against the CPU reference (tests/reference/encoding/frequency_encoding.h).
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "nerf/encoding/frequency_encoding.h"
#include "nerf/sampling/points.h"
#include "reference/encoding/frequency_encoding.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

// The shader reduces 2^k p exactly to f in [-1/4, 1/4], so its error does not grow with the band:
// pi f rounds once (<= 2^-24 relative, ~5e-8 absolute), the float constant pi adds 2.8e-8 relative,
// and the Horner evaluation of the degree-9/8 polynomials adds a few ulp of a value <= 1 (~3e-7).
// 5e-7 absolute covers that (measured: 9e-8 on lavapipe); a naive float sin(2^9 pi p) would be off by ~1e-4.
constexpr double kEncAbs = 5e-7;
constexpr float kSentinel = 12345.0f;

class Encoding : public test::GpuTest {};


// Encodes `inputs` (4 floats each) into a matrix pre-filled with the sentinel.
std::vector<float> encode(Context& ctx, nerf::FrequencyEncoding& enc, const std::vector<float>& inputs, uint32_t stride,
                          uint32_t offset) {
  uint32_t count = uint32_t(inputs.size() / 4);
  auto in = gpu::Buffer::of(ctx, inputs.empty() ? std::vector<float>(4) : inputs);
  std::vector<float> init(std::max<size_t>(1, size_t(count) * stride), kSentinel);
  auto out = gpu::Buffer::of(ctx, init);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    enc.recordForward(rec, {count, in, out, stride, offset});
  });
  return out.download<float>(init.size());
}

// Checks row r of `m` against the double reference: the block, its zero padding, and untouched
// sentinel columns elsewhere.
void expectRow(const float* row, const float* p, const nerf::FrequencyEncoding& enc, uint32_t stride, uint32_t offset,
               double* maxErr) {
  double pd[4] = {p[0], p[1], p[2], p[3]};
  auto ref = ref::frequencyEncoding<double>(pd, enc.inputDims(), enc.levels(), enc.includeInput());
  ASSERT_EQ(ref.size(), enc.outputDims());
  for (uint32_t c = 0; c < stride; ++c) {
    float g = row[c];
    if (c < offset || c >= offset + enc.paddedDims()) {
      ASSERT_EQ(g, kSentinel) << "column " << c << " outside the block was written";
    } else if (c >= offset + enc.outputDims()) {
      ASSERT_EQ(g, 0.0f) << "padding column " << c;
    } else {
      uint32_t j = c - offset;
      if (enc.includeInput() && j < enc.inputDims()) {
        ASSERT_EQ(g, p[j]) << "raw input column " << j;  // a copy, exact
      } else {
        ASSERT_TRUE(test::near(g, ref[j], 0, kEncAbs)) << "column " << j << " p = " << p[0] << "," << p[1] << "," << p[2];
        *maxErr = std::max(*maxErr, std::fabs(g - ref[j]));
      }
    }
  }
}

// Random values in [-1, 1] plus the hard cases: |p| at and just below 1 (where 2^9 pi p is largest),
// tiny values, exact zeros and dyadic values whose bands hit sin/cos zeros exactly.
std::vector<float> hardInputs(uint32_t count, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> v(4 * size_t(count));
  for (auto& x : v) x = u(gen);
  const float special[] = {1.0f, -1.0f, std::nextafter(1.0f, 0.0f), -std::nextafter(1.0f, 0.0f), 0.999f, -0.9990001f,
                           0.0f, -0.0f, 0.5f, 0.25f, 1.0f / 1024, 1e-30f, 0.75f + 1.0f / 4096, 0.3333333f};
  size_t n = sizeof special / sizeof special[0];
  for (size_t i = 0; i < v.size() && i < 4 * n; ++i) v[i] = special[(i * 7) % n];
  return v;
}

}  // namespace

TEST(EncodingReference, SeedValuesAtTwoLevels) {
  // Seed §4.7 / C2: gamma(0.5) = (1, 0, 0, -1), gamma(0.25) = (sqrt2/2, sqrt2/2, 1, 0).
  double half = 0.5, quarter = 0.25;
  auto a = ref::frequencyEncoding<double>(&half, 1, 2, false);
  auto b = ref::frequencyEncoding<double>(&quarter, 1, 2, false);
  const double h = std::sqrt(0.5);
  const double ea[] = {1, 0, 0, -1}, eb[] = {h, h, 1, 0};
  ASSERT_EQ(a.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(a[i], ea[i], 1e-15);
    EXPECT_NEAR(b[i], eb[i], 1e-15);
  }
}

TEST(EncodingReference, DimensionCounts) {
  EXPECT_EQ(ref::frequencyEncodingDims(3, 10, true), 63u);
  EXPECT_EQ(ref::frequencyEncodingDims(3, 4, true), 27u);
  EXPECT_EQ(ref::frequencyEncodingDims(3, 10, false), 60u);
  EXPECT_EQ(ref::frequencyEncodingDims(3, 4, false), 24u);
}

TEST(EncodingReference, PeriodReductionAgreesWithLongDouble) {
  // The reduction must not change the value: compare against sin/cos of the unreduced argument
  // in long double (64-bit mantissa, so 2^9 pi x keeps ~1e-16 relative accuracy).
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 2000; ++i) {
    double x = std::ldexp(u(gen), i % 10);
    long double a = std::numbers::pi_v<long double> * (long double)x;
    EXPECT_NEAR(ref::sinPi(x), double(std::sin(a)), 1e-13) << x;
    EXPECT_NEAR(ref::cosPi(x), double(std::cos(a)), 1e-13) << x;
  }
}

TEST_F(Encoding, SeedValuesOnDevice) {
  nerf::FrequencyEncoding enc(ctx(), 1, 2, false);
  ASSERT_EQ(enc.outputDims(), 4u);
  auto m = encode(ctx(), enc, {0.5f, 0, 0, 0, 0.25f, 0, 0, 0}, 4, 0);
  const float h = std::sqrt(0.5f);
  const float expect[] = {1, 0, 0, -1, h, h, 1, 0};
  for (int i = 0; i < 8; ++i) EXPECT_TRUE(test::near(m[i], expect[i], 0, kEncAbs)) << i;
  EXPECT_EQ(nerf::FrequencyEncoding(ctx(), 3, 10, true).outputDims(), 63u);
  EXPECT_EQ(nerf::FrequencyEncoding(ctx(), 3, 4, true).outputDims(), 27u);
}

TEST_F(Encoding, InterleavingForThreeComponents) {
  // One row, p = (0.5, 0.25, 0), L = 1 with the raw input: (p, sin pi p, cos pi p) per component block.
  nerf::FrequencyEncoding enc(ctx(), 3, 1, true);
  auto m = encode(ctx(), enc, {0.5f, 0.25f, 0.0f, 9.0f}, 12, 0);
  const float h = std::sqrt(0.5f);
  const float expect[] = {0.5f, 0.25f, 0, 1, h, 0, 0, h, 1, 0, 0, 0};
  for (int i = 0; i < 12; ++i) EXPECT_TRUE(test::near(m[i], expect[i], 0, kEncAbs)) << i;
}

TEST_F(Encoding, MatchesReferenceOnHardInputs) {
  struct Config {
    uint32_t dims, levels;
    bool include;
    uint32_t count, extraColumns, offset;
  };
  // Row counts that are not multiples of the 64-wide workgroup; blocks at offset 0 and mid-row.
  const Config configs[] = {{3, 10, true, 1000, 0, 0}, {3, 4, true, 333, 8, 4}, {2, 6, false, 77, 4, 0},
                            {4, 3, true, 65, 0, 8}, {1, 12, false, 129, 4, 4}};
  for (const auto& c : configs) {
    nerf::FrequencyEncoding enc(ctx(), c.dims, c.levels, c.include);
    uint32_t stride = c.offset + enc.paddedDims() + c.extraColumns;
    auto inputs = hardInputs(c.count, c.dims * 100 + c.levels);
    auto m = encode(ctx(), enc, inputs, stride, c.offset);
    double maxErr = 0;
    for (uint32_t r = 0; r < c.count; ++r) {
      expectRow(&m[size_t(r) * stride], &inputs[4 * size_t(r)], enc, stride, c.offset, &maxErr);
      if (HasFatalFailure()) return;
    }
    RecordProperty("max_abs_err_L" + std::to_string(c.levels), std::to_string(maxErr));
    std::printf("encode dims=%u L=%u: max |gpu - ref| = %.3g\n", c.dims, c.levels, maxErr);
  }
}

TEST_F(Encoding, PositionAndDirectionShareOneMatrix) {
  nerf::FrequencyEncoding pos(ctx(), 3, 10, true), dir(ctx(), 3, 4, true);
  const uint32_t count = 70, stride = pos.paddedDims() + dir.paddedDims();  // 64 + 28
  ASSERT_EQ(stride, 92u);
  auto x = hardInputs(count, 1), d = hardInputs(count, 2);
  auto xb = gpu::Buffer::of(ctx(), x), db = gpu::Buffer::of(ctx(), d);
  auto out = gpu::Buffer::of(ctx(), std::vector<float>(size_t(count) * stride, kSentinel));
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    dir.recordForward(rec, {count, db, out, stride, pos.paddedDims()});  // order does not matter: blocks are disjoint
    pos.recordForward(rec, {count, xb, out, stride, 0});
  });
  auto m = out.download<float>();
  for (uint32_t r = 0; r < count; ++r) {
    double e = 0;
    double px[4] = {x[4 * r], x[4 * r + 1], x[4 * r + 2], 0}, pd[4] = {d[4 * r], d[4 * r + 1], d[4 * r + 2], 0};
    auto rx = ref::frequencyEncoding<double>(px, 3, 10, true), rd = ref::frequencyEncoding<double>(pd, 3, 4, true);
    for (uint32_t j = 0; j < stride; ++j) {
      double want = j < 63 ? rx[j] : j < 64 ? 0.0 : j < 64 + 27 ? rd[j - 64] : 0.0;
      e = std::max(e, std::fabs(m[size_t(r) * stride + j] - want));
    }
    ASSERT_LE(e, kEncAbs) << "row " << r;
  }
}

TEST_F(Encoding, EmptyBatchAndBadLayouts) {
  nerf::FrequencyEncoding enc(ctx(), 3, 4, true);
  auto m = encode(ctx(), enc, {}, 28, 0);  // count 0: no dispatch, matrix untouched
  EXPECT_EQ(m[0], kSentinel);
  auto in = gpu::Buffer::of(ctx(), std::vector<float>(16));
  gpu::Buffer out(ctx(), 4 * 64 * 4);
  gpu::Recorder rec(ctx());
  rec.begin();
  EXPECT_THROW(enc.recordForward(rec, {4, in, out, 32, 2}), Error);   // offset not a multiple of 4
  EXPECT_THROW(enc.recordForward(rec, {4, in, out, 30, 0}), Error);   // stride not a multiple of 4
  EXPECT_THROW(enc.recordForward(rec, {4, in, out, 28, 4}), Error);   // block overruns the row
  EXPECT_THROW(enc.recordForward(rec, {5, in, out, 28, 0}), Error);   // more rows than the inputs hold
  rec.end();
  EXPECT_THROW(nerf::FrequencyEncoding(ctx(), 5, 4, true), Error);
}

namespace {

const Aabb kSampleBox{{-1.5f, -0.5f, -2.0f}, {1.5f, 2.5f, 1.0f}};  // not a cube

// SamplePoints on `numRays` random rays (unit directions, as rays.comp writes them) with `n` samples
// each in kSampleBox, against the double reference; returns how many values differ, and
// prints the first.
size_t samplePointsMismatches(Context& ctx, uint32_t numRays, uint32_t n) {
  const Aabb& box = kSampleBox;
  std::mt19937 gen(3);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> rays(8 * size_t(numRays)), samples(2 * size_t(numRays) * n);
  for (uint32_t r = 0; r < numRays; ++r) {
    float d[3] = {u(gen), u(gen), u(gen)};
    float len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; ++k) {
      rays[8 * r + k] = 3.0f * u(gen);
      rays[8 * r + 4 + k] = d[k] / len;
    }
    rays[8 * r + 3] = 0.5f;
    rays[8 * r + 7] = 4.5f;
    for (uint32_t s = 0; s < n; ++s) {
      samples[2 * (size_t(r) * n + s)] = 0.5f + 4.0f * (s + 0.5f * (u(gen) + 1)) / n;
      samples[2 * (size_t(r) * n + s) + 1] = 4.0f / n;
    }
  }
  const size_t count = size_t(numRays) * n;
  auto rb = gpu::Buffer::of(ctx, rays), sb = gpu::Buffer::of(ctx, samples);
  gpu::Buffer pos(ctx, count * nerf::kPointBytes), dir(ctx, count * nerf::kPointBytes);
  nerf::SamplePoints sp(ctx);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    sp.record(rec, {rb, numRays}, sb, n, box, {pos, dir});
    sp.record(rec, {rb, 0}, sb, n, box, {pos, dir});  // empty batch: records nothing
  });
  auto p = pos.download<float>(), d = dir.download<float>();
  // |o| <= 3 and t <= 4.5 give |x| < 8: o + t d rounds to ~1 ulp of 8 (1e-6); the map onto [-1, 1]
  // multiplies by 2 / extent (<= 2/3) and adds a few ulp of 1, so 2e-6 absolute.
  size_t bad = 0;
  auto check = [&](bool ok, size_t s, const char* what) {
    if (!ok && bad++ == 0) ADD_FAILURE() << "sample " << s << ": " << what;
  };
  for (size_t s = 0; s < count; ++s) {
    size_t r = s / n;
    std::array<double, 3> o{rays[8 * r], rays[8 * r + 1], rays[8 * r + 2]};
    std::array<double, 3> dd{rays[8 * r + 4], rays[8 * r + 5], rays[8 * r + 6]};
    auto want = ref::samplePosition<double>(o, dd, samples[2 * s], box);
    for (int k = 0; k < 3; ++k) {
      check(test::near(p[4 * s + k], want[k], 0, 2e-6), s, "position");
      check(d[4 * s + k] == rays[8 * r + 4 + k], s, "direction");
    }
    check(p[4 * s + 3] == 0.0f && d[4 * s + 3] == 0.0f, s, "fourth component");
  }
  return bad;
}

}  // namespace

TEST_F(Encoding, SamplePointsMatchReference) {
  EXPECT_EQ(samplePointsMismatches(ctx(), 45, 7), 0u);  // 315 samples: not a multiple of the workgroup
  // The box corners map onto -1 and +1.
  auto lo = ref::samplePosition<double>({-1.5, -0.5, -2.0}, {1, 1, 1}, 0.0, kSampleBox);
  auto hi = ref::samplePosition<double>({-1.5, -0.5, -2.0}, {1, 1, 1}, 3.0, kSampleBox);
  for (int k = 0; k < 3; ++k) {
    EXPECT_DOUBLE_EQ(lo[k], -1.0);
    EXPECT_DOUBLE_EQ(hi[k], 1.0);
  }
}

// 65,537 rays of 64 samples: 65,537 workgroups of 64, one past what maxComputeWorkGroupCount[0]
// holds on most devices (and under every 65,535 profile), dispatched over x and y.
TEST_F(Encoding, SamplePointsPastTheGroupCountOfOneAxis) {
  EXPECT_EQ(samplePointsMismatches(ctx(), 65537, 64), 0u);
}

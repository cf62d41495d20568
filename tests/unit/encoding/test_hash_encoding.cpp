// encode_hash.comp / encode_hash_backward.comp against the CPU reference (tests/reference/encoding/hash_encoding.h),
// and the reference against first principles (vertex lookup, affine reproduction, finite differences).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "nerf/encoding/hash_encoding.h"
#include "reference/encoding/hash_encoding.h"
#include "vknerf/error.h"

using namespace vknerf;
using ref::HashGridConfig;

namespace {

constexpr float kSentinel = 12345.0f;

class HashEncoding : public test::GpuTest {};

// Test grids, small enough to JIT quickly, each with dense and hashed levels:
//  kPow2:  res 4, 8, 16, 32, 64, 128 (b = 2: exact vertex coordinates); dense while (res+1)^3 <= 4096.
//  kOdd:   res 3, 4, 5 (b = 1.37), F = 1, T = 6: level 0 dense (64 vertices = 64 entries), others hashed.
//  kWide:  res 8, 24 (b = 3), F = 4, T = 8: every level hashed, with many collisions.
//  kEight: res 2, 4, 8, F = 8 (two vec4s per level), T = 7: levels 0 and 1 dense (27, 125 <= 128).
const HashGridConfig kPow2{6, 2, 12, 4, 2.0};
const HashGridConfig kOdd{3, 1, 6, 3, 1.37};
const HashGridConfig kWide{2, 4, 8, 8, 3.0};
const HashGridConfig kEight{3, 8, 7, 2, 2.0};
// kPow2 over a box of three cascades, contracted about its inner quarter.
const HashGridConfig kContracted{6, 2, 12, 4, 2.0, 4};

std::vector<float> randomTable(const HashGridConfig& c, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> t(ref::hashGridParameterCount(c));
  for (auto& x : t) x = u(gen);
  return t;
}

// Random points plus the hard cases: the box boundary (+-1 and the corners), vertices of every
// level (dyadic multiples of 1/64), points on cell faces (one coordinate on a vertex), and a few
// outside the box, which the encoding clamps onto it.
std::vector<float> hardPositions(uint32_t count, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::uniform_int_distribution<int> k(0, 128);
  std::vector<float> v(4 * size_t(count));
  for (uint32_t i = 0; i < count; ++i) {
    float* p = &v[4 * size_t(i)];
    for (int a = 0; a < 3; ++a) p[a] = u(gen);
    p[3] = 3.0f;  // w is ignored
    switch (i % 6) {
      case 0: for (int a = 0; a < 3; ++a) p[a] = (i / 6 >> a) & 1 ? 1.0f : -1.0f; break;  // corners
      case 1: p[i % 3] = (i & 8) ? 1.0f : -1.0f; break;                                    // faces of the box
      case 2: for (int a = 0; a < 3; ++a) p[a] = float(k(gen)) / 64.0f - 1.0f; break;     // grid vertices
      case 3: p[(i / 6) % 3] = float(k(gen)) / 64.0f - 1.0f; break;                      // cell faces
      case 4: if (i % 4 == 0) p[i % 3] = (i & 16) ? 1.25f : -3.0f; break;                // outside
      default: break;
    }
  }
  return v;
}

// Dyadic points (12 fractional bits of u) for which (p + 1) / 2 * res is exact in float for every
// test resolution: float and double pick the same cell and the same w, so the only GPU/reference
// differences in the backward pass are the rounding of weight products and of the summation.
std::vector<float> dyadicPositions(uint32_t count, uint32_t seed, bool runs) {
  std::mt19937 gen(seed);
  std::uniform_int_distribution<int> k(0, 4096);
  std::vector<float> v(4 * size_t(count));
  for (uint32_t i = 0; i < count; ++i) {
    // runs: consecutive samples along a short segment, as along a ray (neighbours share coarse cells).
    if (runs && i % 16) {
      for (int a = 0; a < 3; ++a) v[4 * i + a] = std::clamp(v[4 * (i - 1) + a] + float(k(gen) % 9) / 2048.0f, -1.0f, 1.0f);
      continue;
    }
    for (int a = 0; a < 3; ++a) v[4 * i + a] = float(k(gen)) / 2048.0f - 1.0f;
  }
  return v;
}

std::vector<float> forward(Context& ctx, nerf::HashEncoding& enc, const std::vector<float>& pos,
                           const std::vector<float>& table, uint32_t stride, uint32_t offset) {
  const uint32_t count = uint32_t(pos.size() / 4);
  auto pb = gpu::Buffer::of(ctx, pos.empty() ? std::vector<float>(4) : pos);
  auto tb = gpu::Buffer::of(ctx, table);
  auto out = gpu::Buffer::of(ctx, std::vector<float>(std::max<size_t>(1, size_t(count) * stride), kSentinel));
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    enc.recordForward(rec, {count, pb, out, stride, offset}, tb);
  });
  return out.download<float>();
}

// Bound on |gpu - ref| for level l's features, given max |table| = 1. Mapping p to x = (p+1)/2 * res
// in float moves x by at most res * 2^-23 per axis (one rounding of p + 1 <= 2 and one of the
// product); the trilinear blend changes by at most 2 max|t| per unit of x on each axis: 6 res 2^-23.
// The blend itself (1 - w, two weight products, 8 products and sums) adds < 40 roundings of values
// <= max|t|: 40 * 2^-24.
double forwardTolerance(uint32_t res) { return 6.0 * res * std::ldexp(1.0, -23) + 40 * std::ldexp(1.0, -24); }

void expectForwardMatches(Context& ctx, const HashGridConfig& c, uint32_t count, uint32_t offset, uint32_t extra) {
  nerf::HashEncoding enc(ctx, c);
  const uint32_t stride = offset + enc.paddedDims() + extra, F = c.featuresPerLevel;
  auto pos = hardPositions(count, c.levels * 10 + F);
  auto table = randomTable(c, F);
  std::vector<double> tableD(table.begin(), table.end());
  auto m = forward(ctx, enc, pos, table, stride, offset);
  double maxErrD = 0, maxErrF = 0;
  for (uint32_t r = 0; r < count; ++r) {
    const float* pf = &pos[4 * size_t(r)];
    const double pd[3] = {pf[0], pf[1], pf[2]};
    auto wantD = ref::hashEncoding<double>(c, tableD.data(), pd);
    auto wantF = ref::hashEncoding<float>(c, table.data(), pf);
    const float* row = &m[size_t(r) * stride];
    for (uint32_t j = 0; j < stride; ++j) {
      if (j < offset || j >= offset + enc.paddedDims()) {
        ASSERT_EQ(row[j], kSentinel) << "column " << j << " outside the block was written";
      } else if (j >= offset + enc.outputDims()) {
        ASSERT_EQ(row[j], 0.0f) << "padding column " << j;
      } else {
        const uint32_t f = j - offset;
        // The contraction rounds p' = ((2 - 1/m) / m) q / 2 about 4 times, each by 2^-24 of |p'| <= 1,
        // which moves x = (p' + 1) / 2 * res by 2 res 2^-24 more: 4 res 2^-24 on the blend, per axis.
        const double tol = forwardTolerance(enc.resolution(f / F)) +
                           (c.contraction ? 12.0 * enc.resolution(f / F) * std::ldexp(1.0, -24) : 0.0);
        ASSERT_TRUE(test::near(row[j], wantD[f], 0, tol))
            << "row " << r << " feature " << f << " p = " << pf[0] << ", " << pf[1] << ", " << pf[2];
        ASSERT_TRUE(test::near(row[j], wantF[f], 0, tol)) << "float reference, row " << r << " feature " << f;
        maxErrD = std::max(maxErrD, std::fabs(row[j] - wantD[f]));
        maxErrF = std::max(maxErrF, std::fabs(row[j] - double(wantF[f])));
      }
    }
  }
  std::printf("encode_hash L=%u F=%u T=%u: max |gpu - ref<double>| = %.3g, |gpu - ref<float>| = %.3g\n", c.levels, F,
              c.log2TableSize, maxErrD, maxErrF);
}

// One recordBackward of `n` rows (dFeatures at column 0) into zeroed gradients; returns them.
std::vector<float> backwardFromZero(Context& ctx, nerf::HashEncoding& enc, const std::vector<float>& pos, uint32_t n,
                                    const std::vector<float>& dF, uint32_t stride) {
  auto pb = gpu::Buffer::of(ctx, pos), db = gpu::Buffer::of(ctx, dF);
  gpu::Buffer gb(ctx, enc.parameterCount() * 4);
  gb.zero();
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    enc.recordBackward(rec, {n, pb, db, stride, 0}, gb);
  });
  return gb.download<float>();
}

// recordBackward of two batches (n1 and n2 rows: not workgroup multiples), recorded back to back
// into one gradient buffer that starts non-zero, against the double reference: the result must be
// start + both batches. The second batch binds its rows from row n1 on: n1 a multiple of 16 keeps
// those offsets (16 bytes and a multiple of 4 floats a row) multiples of 256 bytes, the
// minStorageBufferOffsetAlignment of many GPUs. `onePass`: a SortReduce `enc` sorts each batch in one pass (the default
// budget), which allows a tighter bound. Returns the gradients.
std::vector<float> expectBackwardMatches(Context& ctx, nerf::HashEncoding& enc, uint32_t n1, uint32_t n2,
                                         bool onePass, const std::vector<float>* positions = nullptr) {
  const HashGridConfig& c = enc.config();
  const uint32_t F = c.featuresPerLevel, D = enc.outputDims(), offset = 4, stride = offset + enc.paddedDims() + 4;
  EXPECT_EQ(n1 % 16, 0u) << "the second batch's offsets would not be aligned";
  auto pos = positions ? *positions : dyadicPositions(n1 + n2, c.levels + F, true);
  std::vector<float> dF(size_t(n1 + n2) * stride);
  std::mt19937 gen(c.levels);
  std::uniform_real_distribution<float> u(-1, 1);
  for (auto& x : dF) x = u(gen);  // padding and outside columns hold noise that must be ignored
  // Rows whose gradient is exactly 0 (samples behind a ray's early-termination cut, whose atomics
  // the kernel skips), and rows whose first 4 values are 0 and the rest not (a level group, or half
  // of one level at F = 8, that must still be scattered).
  for (uint32_t i = 0; i < n1 + n2; ++i) {
    float* row = &dF[size_t(i) * stride + offset];
    if (i % 5 == 0) std::fill(row, row + enc.paddedDims(), 0.0f);
    else if (i % 7 == 0) std::fill(row, row + 4, 0.0f);
  }
  auto start = randomTable(c, 77);
  auto pb = gpu::Buffer::of(ctx, pos), db = gpu::Buffer::of(ctx, dF), gb = gpu::Buffer::of(ctx, start);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    enc.recordBackward(rec, {n1, pb, db, stride, offset}, gb);
    if (n2)
      enc.recordBackward(rec,
                         {n2, gpu::BufferRange(pb, 16 * n1, 16 * n2),
                          gpu::BufferRange(db, 4ull * stride * n1, 4ull * stride * n2), stride, offset},
                         gb);
  });
  auto g = gb.download<float>();
  // Reference sum, the sum of |terms| and the number of terms per entry.
  std::vector<double> want(start.begin(), start.end()), mag(start.size(), 0.0), terms(start.size(), 0.0);
  for (uint32_t i = 0; i < n1 + n2; ++i) {
    const double p[3] = {pos[4 * i], pos[4 * i + 1], pos[4 * i + 2]};
    std::vector<double> d(D), a(D);
    for (uint32_t j = 0; j < D; ++j) d[j] = dF[size_t(i) * stride + offset + j], a[j] = std::fabs(d[j]);
    ref::hashEncodingBackward<double>(c, p, d.data(), want.data());
    ref::hashEncodingBackward<double>(c, p, a.data(), mag.data());
    for (uint32_t l = 0; l < c.levels; ++l)
      for (auto& k : ref::hashGridCorners<double>(c, l, p))
        for (uint32_t f = 0; f < F; ++f) terms[size_t(k.entry) * F + f] += 1;
  }
  const bool exactSum = onePass && enc.backwardMode() == nerf::HashBackwardMode::SortReduce;
  double maxErr = 0;
  for (size_t e = 0; e < g.size(); ++e) {
    // With dyadic positions cell and w are exact in float, so each term w * dF is off by at most
    // 3 roundings (two weight products, one by dF), and adding n terms plus the start value in
    // any order by at most (n + 1) roundings of the partial sums, each <= start + sum |terms|.
    double bound = (terms[e] + 4) * std::ldexp(1.0, -24) * (std::fabs(start[e]) + mag[e]);
    // SortReduce in one pass per batch adds each batch's terms exactly in fixed point, after
    // rounding each to a grid of 2^(b+e-61) (n <= 2^b terms, max |term| < 2^e): at most
    // n * 2^(b+e-62) <= n^2 2^-60 max in all. Then 2 roundings converting the sum to float and one
    // adding it per batch: independent of n, where the float sum's bound grows with n.
    if (exactSum)
      bound = 9 * std::ldexp(1.0, -24) * (std::fabs(start[e]) + mag[e]) + terms[e] * terms[e] * std::ldexp(mag[e], -60);
    EXPECT_TRUE(test::near(g[e], want[e], 0, bound)) << "entry " << e << " (" << terms[e] << " terms), mode "
                                                     << uint32_t(enc.backwardMode());
    if (!test::near(g[e], want[e], 0, bound)) break;
    maxErr = std::max(maxErr, std::fabs(g[e] - want[e]));
  }
  std::printf("encode_hash_backward mode %u L=%u F=%u: max |gpu - ref| = %.3g\n", uint32_t(enc.backwardMode()),
              c.levels, F, maxErr);
  return g;
}

}  // namespace

TEST(HashEncodingReference, ResolutionsAndDenseLevels) {
  // instant-ngp's standard grid: N_min = 16, b = 1.5 gives 16, 24, 36, 54, 81, ...; a level is dense
  // while (res + 1)^3 <= 2^19 = 524288: 55^3 = 166375 is, 82^3 = 551368 is not.
  const HashGridConfig c{16, 2, 19, 16, 1.5};
  const uint32_t want[] = {16, 24, 36, 54, 81};
  for (uint32_t l = 0; l < 5; ++l) EXPECT_EQ(ref::hashGridResolution(c, l), want[l]) << l;
  for (uint32_t l = 0; l < 16; ++l) EXPECT_EQ(ref::hashGridDense(c, l), l < 4) << l;
  EXPECT_EQ(ref::hashGridParameterCount(c), size_t(16) * 524288 * 2);
  // b = 2 is exact: 4 * 2^5 = 128 must not floor to 127.
  EXPECT_EQ(ref::hashGridResolution(kPow2, 5), 128u);
  EXPECT_EQ(ref::hashGridResolution(kOdd, 2), 5u);  // floor(3 * 1.37^2) = floor(5.6307)
}

// The used runs (what Adam steps): every entry a lookup reaches lies inside them, including the box's
// far corner (u = 1) and clamped outside points; a dense level's run is exactly its (res + 1)^3
// entries, so its slot's end is left out; the hashed levels' slots merge into one run.
TEST(HashEncodingReference, UsedRunsHoldEveryReachableEntry) {
  const HashGridConfig c{8, 2, 13, 4, 1.6};  // 4, 6, 10, 16 dense ((res + 1)^3 <= 8192), then 26.. hashed
  const auto runs = ref::hashGridUsedRuns(c);
  ASSERT_EQ(runs.size(), 5u);
  for (uint32_t l = 0; l < 4; ++l) {
    ASSERT_TRUE(ref::hashGridDense(c, l)) << l;
    const size_t vertices = ref::hashGridResolution(c, l) + 1;
    EXPECT_EQ(runs[l].first, size_t(l) * 8192 * 2) << l;
    EXPECT_EQ(runs[l].count, vertices * vertices * vertices * 2) << l;
  }
  EXPECT_FALSE(ref::hashGridDense(c, 4));
  EXPECT_EQ(runs[4].first, size_t(4) * 8192 * 2);
  EXPECT_EQ(runs[4].first + runs[4].count, ref::hashGridParameterCount(c));
  auto used = [&](size_t f) {
    for (const auto& r : runs)
      if (f >= r.first && f < r.first + r.count) return true;
    return false;
  };
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  std::vector<std::array<double, 3>> points = {{1, 1, 1}, {-1, -1, -1}, {1, -1, 1}};
  for (int i = 0; i < 2000; ++i) points.push_back({u(gen), u(gen), u(gen)});
  for (const auto& p : points)
    for (uint32_t l = 0; l < c.levels; ++l)
      for (const auto& k : ref::hashGridCorners<double>(c, l, p.data()))
        for (uint32_t f = 0; f < c.featuresPerLevel; ++f)
          ASSERT_TRUE(used(size_t(k.entry) * c.featuresPerLevel + f)) << "level " << l << " entry " << k.entry;
}

TEST(HashEncodingReference, VertexReturnsItsTableEntry) {
  // At a grid vertex one corner has weight 1: the feature is that vertex's entry, at the documented
  // index (dense: x + (res+1)(y + (res+1) z); hashed: x ^ 2654435761 y ^ 805459861 z mod 2^T).
  auto table = randomTable(kPow2, 5);
  std::vector<double> t(table.begin(), table.end());
  const uint32_t v[][3] = {{0, 0, 0}, {128, 128, 128}, {3, 77, 128}, {64, 1, 99}};
  for (auto& vx : v) {
    const double p[3] = {vx[0] / 64.0 - 1, vx[1] / 64.0 - 1, vx[2] / 64.0 - 1};
    auto f = ref::hashEncoding<double>(kPow2, t.data(), p);
    for (uint32_t l = 0; l < kPow2.levels; ++l) {
      const uint32_t res = ref::hashGridResolution(kPow2, l), s = 128 / res;
      const uint32_t x = vx[0] / s, y = vx[1] / s, z = vx[2] / s;
      if (vx[0] % s || vx[1] % s || vx[2] % s) continue;  // not a vertex of this level
      uint64_t idx = ref::hashGridDense(kPow2, l)
                         ? x + uint64_t(res + 1) * (y + uint64_t(res + 1) * z)
                         : (uint64_t(x) ^ (uint64_t(y) * 2654435761ull) ^ (uint64_t(z) * 805459861ull)) % 4096;
      for (uint32_t k = 0; k < 2; ++k) EXPECT_EQ(f[l * 2 + k], t[(l * 4096 + idx) * 2 + k]) << "level " << l;
    }
  }
}

TEST(HashEncodingReference, WeightsArePartitionOfUnityAndReproduceAffineFields) {
  // On a dense level a table holding an affine function of the vertex coordinates is reproduced
  // exactly (to rounding) anywhere: trilinear interpolation is exact for affine functions.
  const HashGridConfig c{1, 1, 12, 7, 1.0};  // res 7, 512 vertices: dense
  ASSERT_TRUE(ref::hashGridDense(c, 0));
  std::vector<double> t(ref::hashGridParameterCount(c));
  for (uint32_t z = 0; z <= 7; ++z)
    for (uint32_t y = 0; y <= 7; ++y)
      for (uint32_t x = 0; x <= 7; ++x) t[x + 8 * (y + 8 * z)] = 0.5 + 0.3 * x - 0.2 * y + 0.7 * z;
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 500; ++i) {
    const double p[3] = {u(gen), u(gen), i == 0 ? 1.0 : u(gen)};
    auto corners = ref::hashGridCorners<double>(c, 0, p);
    double sum = 0;
    for (auto& k : corners) {
      EXPECT_GE(k.weight, 0.0);
      sum += k.weight;
    }
    EXPECT_NEAR(sum, 1.0, 1e-14);
    double gx = (p[0] + 1) / 2 * 7, gy = (p[1] + 1) / 2 * 7, gz = (p[2] + 1) / 2 * 7;
    EXPECT_NEAR(ref::hashEncoding<double>(c, t.data(), p)[0], 0.5 + 0.3 * gx - 0.2 * gy + 0.7 * gz, 1e-13);
  }
}

TEST(HashEncodingReference, GradientMatchesFiniteDifferences) {
  // S(table) = sum_i dF_i . features(p_i); its gradient from hashEncodingBackward against central
  // differences of S in double. S is linear in the table, so the difference quotient is exact up to
  // rounding of S (~1e-15 relative): 1e-9 absolute is generous and still catches any misplaced or
  // mis-weighted contribution (weights are O(0.01..1)).
  for (const auto& c : {kPow2, kOdd, kWide, kEight}) {
    auto tf = randomTable(c, 9);
    std::vector<double> t(tf.begin(), tf.end());
    const uint32_t n = 6, D = c.levels * c.featuresPerLevel;
    auto pf = hardPositions(n, 4);
    std::vector<double> p(pf.begin(), pf.end()), dF(size_t(n) * D);
    std::mt19937 gen(2);
    std::uniform_real_distribution<double> u(-1, 1);
    for (auto& x : dF) x = u(gen);
    std::vector<double> g(t.size(), 0.0);
    for (uint32_t i = 0; i < n; ++i) ref::hashEncodingBackward<double>(c, &p[4 * i], &dF[size_t(i) * D], g.data());
    auto S = [&] {
      double s = 0;
      for (uint32_t i = 0; i < n; ++i) {
        auto f = ref::hashEncoding<double>(c, t.data(), &p[4 * i]);
        for (uint32_t j = 0; j < D; ++j) s += dF[size_t(i) * D + j] * f[j];
      }
      return s;
    };
    // Every touched entry, and untouched ones (gradient 0) spread over the table.
    std::vector<size_t> check;
    for (size_t e = 0; e < g.size(); ++e)
      if (g[e] != 0 || e % 97 == 0) check.push_back(e);
    ASSERT_GT(check.size(), 8u);
    const double h = 1e-3;
    for (size_t e : check) {
      const double saved = t[e];
      t[e] = saved + h;
      const double up = S();
      t[e] = saved - h;
      const double down = S();
      t[e] = saved;
      EXPECT_NEAR(g[e], (up - down) / (2 * h), 1e-9) << "entry " << e << " levels " << c.levels;
    }
  }
}

// The contraction about the inner cube [-1/S, 1/S]^3: the inner cube stays (halved into the grid's
// middle half), a point at max-norm m = |S p|_inf > 1 lands at max-norm (2 - 1/m) / 2 on the same ray
// from the centre, so the box (m <= S) stays inside [-1, 1]^3; continuous across the inner cube's faces.
TEST(HashEncodingReference, ContractionKeepsTheInnerCubeAndSqueezesTheRest) {
  const uint32_t S = 8;
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 1000; ++i) {
    const double p[3] = {u(gen), u(gen), u(gen)};
    const auto c = ref::hashGridContract(p, S);
    const double m = S * std::max({std::fabs(p[0]), std::fabs(p[1]), std::fabs(p[2])});
    const double cm = std::max({std::fabs(c[0]), std::fabs(c[1]), std::fabs(c[2])});
    EXPECT_NEAR(cm, m <= 1 ? m / 2 : (2 - 1 / m) / 2, 1e-15);
    EXPECT_LT(cm, 1.0);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(c[a] * m, cm * S * p[a], 1e-14) << "not on p's ray";
  }
  const double face[3] = {1.0 / S, 0.3 / S, -0.7 / S}, beyond[3] = {(1.0 + 1e-9) / S, 0.3 / S, -0.7 / S};
  const auto a = ref::hashGridContract(face, S), b = ref::hashGridContract(beyond, S);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 1e-9);
  const double corner[3] = {1, -1, 1};
  EXPECT_DOUBLE_EQ(ref::hashGridContract(corner, S)[1], -(2 - 1.0 / S) / 2);
  EXPECT_EQ(ref::hashGridContract(corner, 0)[1], -1.0);  // 0: no contraction
}

TEST(HashEncodingReference, InitialParametersAreSmallUniformAndSeeded) {
  auto a = ref::hashGridInitialParameters(kPow2, 1), b = ref::hashGridInitialParameters(kPow2, 1);
  auto c = ref::hashGridInitialParameters(kPow2, 2);
  ASSERT_EQ(a.size(), ref::hashGridParameterCount(kPow2));
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  double mean = 0, lo = 1, hi = -1;
  for (float x : a) mean += x, lo = std::min<double>(lo, x), hi = std::max<double>(hi, x);
  mean /= double(a.size());
  EXPECT_GE(lo, -1e-4);
  EXPECT_LE(hi, 1e-4);
  EXPECT_LT(lo, -0.99e-4);  // 49152 draws reach both ends of the interval
  EXPECT_GT(hi, 0.99e-4);
  EXPECT_LT(std::fabs(mean), 3e-6);  // sd of the mean: 1e-4 / sqrt(3 * 49152) = 2.6e-7
}

TEST_F(HashEncoding, ForwardMatchesReference) {
  // Row counts that are not multiples of the 64-wide workgroup; blocks at offset 0 and mid-row.
  expectForwardMatches(ctx(), kPow2, 1000, 0, 0);
  expectForwardMatches(ctx(), kOdd, 333, 4, 4);
  expectForwardMatches(ctx(), kWide, 65, 8, 0);
  expectForwardMatches(ctx(), kEight, 200, 4, 4);
  expectForwardMatches(ctx(), kContracted, 600, 4, 0);
}

TEST_F(HashEncoding, BackwardMatchesReferenceAndAccumulates) {
  for (auto mode : {nerf::HashBackwardMode::Atomic, nerf::HashBackwardMode::SubgroupMerged,
                    nerf::HashBackwardMode::SortReduce, nerf::HashBackwardMode::CompareSwap})
    for (const auto& c : {kPow2, kOdd, kWide, kEight}) {
      if (!test::deviceRuns(mode)) continue;
      nerf::HashEncoding enc(ctx(), c, mode);
      expectBackwardMatches(ctx(), enc, 784, 130, true);
    }
}

// Positions whose contraction is exact in float (S = 4): dyadic points inside the inner cube
// (p' = 2 p), and points with |4 p|_inf = 2 or 4, where (2 - 1/m) / m = 3/4 or 7/16: the device's
// cells and in-cell positions equal the reference's, so expectBackwardMatches' bound holds as it is.
std::vector<float> exactlyContractedPositions(uint32_t count, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_int_distribution<int> k(-512, 512);
  std::vector<float> v(4 * size_t(count), 0.0f);
  for (uint32_t i = 0; i < count; ++i) {
    float* p = &v[4 * size_t(i)];
    const float m = i % 3 == 0 ? 1.0f : i % 3 == 1 ? 2.0f : 4.0f;  // |4 p|_inf at most / exactly
    for (int a = 0; a < 3; ++a) p[a] = float(k(gen)) / 512.0f * m / 4.0f;
    if (m > 1.0f) p[i % 3] = (i & 4 ? m : -m) / 4.0f;
  }
  return v;
}

TEST_F(HashEncoding, BackwardThroughTheContractionMatchesReference) {
  const auto positions = exactlyContractedPositions(914, 3);
  for (auto mode : {nerf::HashBackwardMode::Atomic, nerf::HashBackwardMode::SortReduce, nerf::HashBackwardMode::CompareSwap}) {
    if (!test::deviceRuns(mode)) continue;
    nerf::HashEncoding enc(ctx(), kContracted, mode);
    expectBackwardMatches(ctx(), enc, 784, 130, true, &positions);
  }
}

TEST_F(HashEncoding, SortReduceInManyPasses) {
  // A slot budget of 800 contributions: 100 rows and one level per pass, so the 784 + 130 rows go
  // in 8 + 2 row ranges of 4..6 level passes each, every pass adding into the same gradients.
  for (const auto& c : {kPow2, kOdd, kEight}) {
    nerf::HashEncoding enc(ctx(), c, nerf::HashBackwardMode::SortReduce);
    enc.setSortSlotBudget(800);
    expectBackwardMatches(ctx(), enc, 784, 130, false);
  }
  nerf::HashEncoding enc(ctx(), kOdd, nerf::HashBackwardMode::SortReduce);
  EXPECT_THROW(enc.setSortSlotBudget(7), Error);  // not even one sample's 8 corners
  // 2^24 entries in a level: more than one dispatch of the prefix sum covers on lavapipe (65535 * 256).
  if ((uint64_t(1) << 24) > uint64_t(ctx().properties().limits.maxComputeWorkGroupCount[0]) * 256)
    EXPECT_THROW(nerf::HashEncoding(ctx(), HashGridConfig{1, 1, 24, 4, 2.0}, nerf::HashBackwardMode::SortReduce), Error);
}

TEST_F(HashEncoding, SortReduceHotEntryIsCompleteAndDeterministic) {
  // 70,000 samples in one cell of both (dense) levels: each of its 8 corner entries per level gets
  // 70,000 contributions. lavapipe ends a shader's loops silently after 65,535 iterations in all,
  // so a reduction looping over an entry's slots in one invocation would drop the terms past that
  // (and pass with fewer samples); encode_hash_backward_reduce.comp splits entries into chunks.
  const HashGridConfig hot{2, 2, 10, 2, 2.0};  // res 2 and 4, 27 and 125 entries: dense
  const uint32_t n = 70000;
  std::mt19937 gen(5);
  std::uniform_int_distribution<int> k(0, 1023);
  std::vector<float> pos(4 * size_t(n), 0.0f);
  for (uint32_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) pos[4 * i + a] = float(k(gen)) / 2048.0f - 1.0f;  // [-1, -0.5): cell 0 of both
  nerf::HashEncoding enc(ctx(), hot, nerf::HashBackwardMode::SortReduce);
  auto a = expectBackwardMatches(ctx(), enc, n, 0, true, &pos);
  // Fixed-point sums do not depend on the order the scatter's atomics left the slots in (with 2
  // threads it changes from run to run): a second run gives the same bits.
  auto b = expectBackwardMatches(ctx(), enc, n, 0, true, &pos);
  EXPECT_EQ(a, b);
}

TEST_F(HashEncoding, SortReduceNonFiniteTermsGiveNonFiniteGradients) {
  // Fixed point cannot hold inf or NaN; the reduce must still not turn them into finite garbage (a
  // diverging step would go unnoticed). Entries with a non-finite term get a non-finite gradient,
  // on a hot dense entry (many slots, spanning chunks) and on sparse ones; all others stay finite.
  const HashGridConfig c = kPow2;
  nerf::HashEncoding enc(ctx(), c, nerf::HashBackwardMode::SortReduce);
  const uint32_t n = 3000, stride = enc.paddedDims(), F = c.featuresPerLevel;
  auto pos = dyadicPositions(n, 4, true);
  std::vector<float> dF(size_t(n) * stride, 0.5f);
  dF[size_t(7) * stride + 0] = std::nanf("");                                  // level 0, feature 0
  dF[size_t(11) * stride + 5 * F + 1] = std::numeric_limits<float>::infinity();  // level 5 (hashed), feature 1
  dF[size_t(13) * stride + 2 * F + 0] = -std::numeric_limits<float>::infinity(); // level 2, feature 0
  auto g = backwardFromZero(ctx(), enc, pos, n, dF, stride);
  std::vector<bool> bad(g.size(), false);
  std::vector<uint32_t> terms(g.size(), 0);
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t l = 0; l < c.levels; ++l)
      for (auto& k : ref::hashGridCorners<float>(c, l, &pos[4 * size_t(i)]))
        for (uint32_t f = 0; f < F; ++f) {
          terms[size_t(k.entry) * F + f] += 1;
          if (!std::isfinite(dF[size_t(i) * stride + l * F + f])) bad[size_t(k.entry) * F + f] = true;
        }
  size_t nBad = 0;
  uint32_t most = 0;
  for (size_t e = 0; e < g.size(); ++e) {
    ASSERT_EQ(!std::isfinite(g[e]), bool(bad[e])) << "entry " << e << " = " << g[e];
    nBad += bad[e];
    if (bad[e]) most = std::max(most, terms[e]);
  }
  EXPECT_EQ(nBad, 24u);  // 8 corners x 3 bad terms
  EXPECT_GT(most, 256u);  // more slots than a reduce chunk holds: the spanning path is covered
}

TEST_F(HashEncoding, SortReduceOnBoxBoundaryAndOutside) {
  // hardPositions: box corners and faces, vertices and cell faces of every level, points outside the
  // box (clamped onto it). Against sums of the float reference's corners, which pick the shader's
  // cells and weights (ref::hashGridCorners<float>, step for step): each GPU term is one rounding of
  // w * dF from the reference's, the fixed-point sum adds n^2 2^-60 max, the conversion 2 roundings
  // and the add into zeroed gradients none; 8 roundings of sum |terms| leave room for a last-bit
  // difference in a weight from the compiler contracting the reference's arithmetic.
  for (const auto& c : {kPow2, kOdd, kWide, kEight}) {
    nerf::HashEncoding enc(ctx(), c, nerf::HashBackwardMode::SortReduce);
    const uint32_t n = 600, D = enc.outputDims(), stride = enc.paddedDims(), F = c.featuresPerLevel;
    auto pos = hardPositions(n, 11);
    std::vector<float> dF(size_t(n) * stride);
    std::mt19937 gen(3);
    std::uniform_real_distribution<float> u(-1, 1);
    for (auto& x : dF) x = u(gen);
    auto g = backwardFromZero(ctx(), enc, pos, n, dF, stride);
    std::vector<double> want(g.size(), 0.0), mag(g.size(), 0.0), terms(g.size(), 0.0);
    for (uint32_t i = 0; i < n; ++i)
      for (uint32_t l = 0; l < c.levels; ++l)
        for (auto& k : ref::hashGridCorners<float>(c, l, &pos[4 * size_t(i)]))
          for (uint32_t f = 0; f < F; ++f) {
            const double t = double(k.weight) * dF[size_t(i) * stride + l * F + f];
            want[size_t(k.entry) * F + f] += t, mag[size_t(k.entry) * F + f] += std::fabs(t);
            terms[size_t(k.entry) * F + f] += 1;
          }
    (void)D;
    for (size_t e = 0; e < g.size(); ++e) {
      const double bound = 8 * std::ldexp(mag[e], -24) + terms[e] * terms[e] * std::ldexp(mag[e], -60);
      ASSERT_TRUE(test::near(g[e], want[e], 0, bound)) << "entry " << e << " (" << terms[e] << " terms) L=" << c.levels;
    }
  }
}

TEST_F(HashEncoding, EmptyBatchesAndBadLayouts) {
  nerf::HashEncoding enc(ctx(), kOdd);
  EXPECT_EQ(enc.outputDims(), 3u);
  EXPECT_EQ(enc.paddedDims(), 4u);
  EXPECT_EQ(enc.parameterCount(), 3u * 64);
  auto table = randomTable(kOdd, 1);
  auto m = forward(ctx(), enc, {}, table, 4, 0);  // count 0: nothing recorded, matrix untouched
  EXPECT_EQ(m[0], kSentinel);
  auto pos = gpu::Buffer::of(ctx(), std::vector<float>(16, 0.0f));
  auto tb = gpu::Buffer::of(ctx(), table), gb = gpu::Buffer::of(ctx(), table);
  gpu::Buffer out(ctx(), 4 * 64 * 4), small(ctx(), 4 * 10);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    enc.recordBackward(rec, {0, pos, out, 4, 0}, gb);             // count 0: no dispatch
    EXPECT_THROW(enc.recordForward(rec, {4, pos, out, 8, 2}, tb), Error);   // offset not a multiple of 4
    EXPECT_THROW(enc.recordForward(rec, {4, pos, out, 6, 0}, tb), Error);   // stride not a multiple of 4
    EXPECT_THROW(enc.recordForward(rec, {4, pos, out, 4, 4}, tb), Error);   // block overruns the row
    EXPECT_THROW(enc.recordForward(rec, {5, pos, out, 4, 0}, tb), Error);   // more rows than positions
    EXPECT_THROW(enc.recordForward(rec, {4, pos, out, 4, 0}, small), Error);  // table too small
    EXPECT_THROW(enc.recordBackward(rec, {4, pos, out, 4, 0}, small), Error); // gradient too small
  });
  EXPECT_EQ(gb.download<float>(), table);  // the empty backward added nothing
  EXPECT_THROW(nerf::HashEncoding(ctx(), HashGridConfig{0, 2, 12, 4, 2.0}), Error);
  EXPECT_THROW(nerf::HashEncoding(ctx(), HashGridConfig{4, 3, 12, 4, 2.0}), Error);
  EXPECT_THROW(nerf::HashEncoding(ctx(), HashGridConfig{4, 2, 12, 4, 0.5}), Error);
  EXPECT_THROW(nerf::HashEncoding(ctx(), HashGridConfig{16, 8, 24, 16, 1.5}), Error);  // 2 GiB table
}

TEST_F(HashEncoding, BackwardWithoutFloatAtomicsFailsClearly) {
  // The same device adopted as if the caller had not enabled shaderBufferFloat32AtomicAdd: the
  // forward pass (inference) still works, the Atomic backward pass refuses with an Error, not a bad
  // shader.
  auto adopted = Context::adopt({ctx().instance(), ctx().physicalDevice(), ctx().device(), ctx().queueFamily(),
                                 ctx().queue(), false});
  ASSERT_FALSE(adopted->floatAtomics());
  nerf::HashEncoding enc(*adopted, kOdd, nerf::HashBackwardMode::Atomic);
  auto table = randomTable(kOdd, 3);
  auto pos = hardPositions(10, 1);
  auto m = forward(*adopted, enc, pos, table, 4, 0);
  const double p[3] = {pos[0], pos[1], pos[2]};
  std::vector<double> t(table.begin(), table.end());
  EXPECT_TRUE(test::near(m[0], ref::hashEncoding<double>(kOdd, t.data(), p)[0], 0, forwardTolerance(enc.resolution(0))));
  auto pb = gpu::Buffer::of(*adopted, pos), db = gpu::Buffer::of(*adopted, m), gb = gpu::Buffer::of(*adopted, table);
  gpu::Recorder rec(*adopted);
  rec.begin();
  try {
    enc.recordBackward(rec, {10, pb, db, 4, 0}, gb);
    ADD_FAILURE() << "recordBackward did not throw";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("float atomics"), std::string::npos) << e.what();
  }
  rec.end();
  // SortReduce and CompareSwap need no float atomics: on the same device they compute the
  // gradient, and CompareSwap is what that device gets without asking (nerf/network/gradient_paths.h).
  nerf::HashEncoding sorted(*adopted, kPow2, nerf::HashBackwardMode::SortReduce);
  expectBackwardMatches(*adopted, sorted, 304, 40, true);
  nerf::HashEncoding swapped(*adopted, kPow2);
  EXPECT_EQ(swapped.backwardMode(), nerf::HashBackwardMode::CompareSwap);
  expectBackwardMatches(*adopted, swapped, 304, 40, true);
  // A device with them gets Atomic, the faster there.
  EXPECT_EQ(nerf::HashEncoding(ctx(), kPow2).backwardMode(),
            ctx().floatAtomics() ? nerf::HashBackwardMode::Atomic : nerf::HashBackwardMode::CompareSwap);
}

TEST_F(HashEncoding, TableInsideALargerBuffer) {
  // Parameters often live in one buffer with the network's: the table bound at an offset must give
  // the same features, and the backward pass must touch only the table's own range.
  nerf::HashEncoding enc(ctx(), kPow2);
  const size_t P = enc.parameterCount(), lead = 64, tail = 100;
  auto table = randomTable(kPow2, 8);
  std::vector<float> big(lead + P + tail, kSentinel);
  std::copy(table.begin(), table.end(), big.begin() + lead);
  auto pos = dyadicPositions(150, 3, false);
  const uint32_t stride = enc.paddedDims();
  auto bb = gpu::Buffer::of(ctx(), big), pb = gpu::Buffer::of(ctx(), pos);
  gpu::Buffer feat(ctx(), 150 * stride * 4);
  gpu::BufferRange inner(bb, lead * 4, VK_WHOLE_SIZE);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    enc.recordForward(rec, {150, pb, feat, stride, 0}, inner);
    enc.recordBackward(rec, {150, pb, feat, stride, 0}, inner);  // dFeatures = features, into the table itself
  });
  EXPECT_EQ(feat.download<float>(), forward(ctx(), enc, pos, table, stride, 0));
  auto after = bb.download<float>();
  for (size_t i = 0; i < lead; ++i) ASSERT_EQ(after[i], kSentinel) << i;
  for (size_t i = lead + P; i < after.size(); ++i) ASSERT_EQ(after[i], kSentinel) << i;
  size_t changed = 0;
  for (size_t i = 0; i < P; ++i) changed += after[lead + i] != table[i];
  EXPECT_GT(changed, 100u);
}

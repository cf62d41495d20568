// encode_sh.comp against the CPU reference (tests/reference/encoding/sh_encoding.h), and the reference basis
// against its defining property: orthonormality on the unit sphere.
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "nerf/encoding/sh_encoding.h"
#include "reference/encoding/sh_encoding.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

// Each coefficient is a constant (<= 2.9, rounded to float: 2^-24 relative) times a polynomial of
// degree <= 3 in unit components; the polynomial takes at most ~6 float roundings of intermediates
// no larger than 5 (half an ulp: 2.4e-7 each), so |error| <= 2.9 * 6 * 2.4e-7 ~ 4.2e-6 in the worst
// case; 5e-6 absolute. (Measured on lavapipe: 1.5e-7.)
constexpr double kShAbs = 5e-6;
constexpr float kSentinel = 12345.0f;

class ShEncoding : public test::GpuTest {};

// Gauss-Legendre nodes and weights on [-1, 1] by Newton's method on P_n.
void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.resize(n), w.resize(n);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) {
        double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      double dz = p1 / dp;
      z -= dz;
      if (std::fabs(dz) < 1e-16) break;
    }
    x[i] = z, w[i] = 2 / ((1 - z * z) * dp * dp);
  }
}

// Unit directions: the axes, the diagonals, and random ones.
std::vector<float> directions(uint32_t count, uint32_t seed) {
  std::mt19937 gen(seed);
  std::normal_distribution<float> g;
  std::vector<float> v(4 * size_t(count));
  for (uint32_t i = 0; i < count; ++i) {
    float d[3] = {g(gen), g(gen), g(gen)};
    if (i < 6) d[0] = d[1] = d[2] = 0, d[i / 2] = (i % 2) ? -1.0f : 1.0f;
    if (i >= 6 && i < 14) d[0] = (i & 1) ? 1 : -1, d[1] = (i & 2) ? 1 : -1, d[2] = (i & 4) ? 1 : -1;
    float len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; ++k) v[4 * i + k] = d[k] / len;
    v[4 * i + 3] = 7.0f;  // w is ignored
  }
  return v;
}

std::vector<float> encode(Context& ctx, nerf::ShEncoding& enc, const std::vector<float>& dirs, uint32_t stride,
                          uint32_t offset) {
  uint32_t count = uint32_t(dirs.size() / 4);
  auto in = gpu::Buffer::of(ctx, dirs.empty() ? std::vector<float>(4) : dirs);
  std::vector<float> init(std::max<size_t>(1, size_t(count) * stride), kSentinel);
  auto out = gpu::Buffer::of(ctx, init);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    enc.recordForward(rec, {count, in, out, stride, offset});
  });
  return out.download<float>(init.size());
}

}  // namespace

TEST(ShEncodingReference, DegreeZeroConstant) {
  const double d[3] = {0.6, 0.0, 0.8};
  auto y = ref::shEncoding<double>(d, 1);
  ASSERT_EQ(y.size(), 1u);
  EXPECT_NEAR(y[0], 0.5 / std::sqrt(std::numbers::pi), 1e-16);
  EXPECT_EQ(ref::shEncoding<double>(d, 4).size(), 16u);
  EXPECT_EQ(ref::shEncoding<double>(d, 3).size(), 9u);
}

TEST(ShEncodingReference, OrthonormalOnTheSphere) {
  // dOmega = dz dphi. Products of two bands <= 3 are polynomials of degree <= 6 in (x, y, z); with
  // x = s cos(phi), y = s sin(phi), s = sqrt(1 - z^2), the terms odd in s integrate to 0 over phi
  // and the rest are polynomials in z: 8 Gauss-Legendre nodes in z (exact to degree 15) and 16
  // equal steps in phi (exact for trigonometric degree < 16; here <= 6) integrate exactly, so the
  // Gram matrix must be the identity to rounding.
  std::vector<double> zs, ws;
  gaussLegendre(8, zs, ws);
  const int nPhi = 16;
  double gram[16][16] = {};
  for (size_t i = 0; i < zs.size(); ++i)
    for (int j = 0; j < nPhi; ++j) {
      double phi = 2 * std::numbers::pi * j / nPhi, s = std::sqrt(1 - zs[i] * zs[i]);
      double d[3] = {s * std::cos(phi), s * std::sin(phi), zs[i]};
      auto y = ref::shEncoding<double>(d, 4);
      for (int a = 0; a < 16; ++a)
        for (int b = 0; b < 16; ++b) gram[a][b] += ws[i] * (2 * std::numbers::pi / nPhi) * y[a] * y[b];
    }
  for (int a = 0; a < 16; ++a)
    for (int b = 0; b < 16; ++b) EXPECT_NEAR(gram[a][b], a == b ? 1.0 : 0.0, 1e-12) << a << "," << b;
}

TEST(ShEncodingReference, BandOneIsTheDirection) {
  // Degree-1 band is sqrt(3/(4 pi)) (-y, z, -x) in tcnn's order and signs.
  const double d[3] = {0.48, 0.6, 0.64}, c = std::sqrt(3 / (4 * std::numbers::pi));
  auto y = ref::shEncoding<double>(d, 2);
  EXPECT_NEAR(y[1], -c * d[1], 1e-15);
  EXPECT_NEAR(y[2], c * d[2], 1e-15);
  EXPECT_NEAR(y[3], -c * d[0], 1e-15);
}

TEST_F(ShEncoding, MatchesReference) {
  struct Config {
    uint32_t degree, count, offset, extra;
  };
  // 333 and 65 rows: not multiples of the 64-wide workgroup; blocks at offset 0 and mid-row.
  const Config configs[] = {{4, 333, 0, 0}, {4, 65, 8, 4}, {3, 100, 4, 0}, {2, 70, 0, 4}, {1, 9, 4, 4}};
  for (const auto& c : configs) {
    nerf::ShEncoding enc(ctx(), c.degree);
    ASSERT_EQ(enc.outputDims(), c.degree * c.degree);
    const uint32_t stride = c.offset + enc.paddedDims() + c.extra;
    auto dirs = directions(c.count, c.degree * 1000 + c.count);
    auto m = encode(ctx(), enc, dirs, stride, c.offset);
    double maxErr = 0;
    for (uint32_t r = 0; r < c.count; ++r) {
      const double d[3] = {dirs[4 * r], dirs[4 * r + 1], dirs[4 * r + 2]};
      auto want = ref::shEncoding<double>(d, c.degree);
      for (uint32_t j = 0; j < stride; ++j) {
        float g = m[size_t(r) * stride + j];
        if (j < c.offset || j >= c.offset + enc.paddedDims()) {
          ASSERT_EQ(g, kSentinel) << "column " << j << " outside the block was written";
        } else if (j >= c.offset + enc.outputDims()) {
          ASSERT_EQ(g, 0.0f) << "padding column " << j;
        } else {
          ASSERT_TRUE(test::near(g, want[j - c.offset], 0, kShAbs)) << "row " << r << " coefficient " << j - c.offset;
          maxErr = std::max(maxErr, std::fabs(g - want[j - c.offset]));
        }
      }
    }
    std::printf("encode_sh degree %u: max |gpu - ref| = %.3g\n", c.degree, maxErr);
  }
}

TEST_F(ShEncoding, EmptyBatchAndBadLayouts) {
  nerf::ShEncoding enc(ctx());
  auto m = encode(ctx(), enc, {}, 16, 0);
  EXPECT_EQ(m[0], kSentinel);
  auto in = gpu::Buffer::of(ctx(), std::vector<float>(16));
  gpu::Buffer out(ctx(), 4 * 64 * 4);
  gpu::Recorder rec(ctx());
  rec.begin();
  EXPECT_THROW(enc.recordForward(rec, {4, in, out, 32, 2}), Error);   // offset not a multiple of 4
  EXPECT_THROW(enc.recordForward(rec, {4, in, out, 18, 0}), Error);   // stride not a multiple of 4
  EXPECT_THROW(enc.recordForward(rec, {4, in, out, 16, 4}), Error);   // block overruns the row
  EXPECT_THROW(enc.recordForward(rec, {5, in, out, 16, 0}), Error);   // more rows than the inputs hold
  rec.end();
  EXPECT_THROW(nerf::ShEncoding(ctx(), 5), Error);
  EXPECT_THROW(nerf::ShEncoding(ctx(), 0), Error);
}

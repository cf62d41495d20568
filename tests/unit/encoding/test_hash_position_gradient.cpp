// encode_hash_position_gradient.comp (HashEncoding::recordPositionGradient: dL/dp for camera
// refinement) against central differences of the CPU reference in double (tests/reference/encoding/hash_encoding.h),
// and the same gradient from the table's backward pass (encode_hash_backward_position.comp).
#include <algorithm>
#include <cmath>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/encoding/hash_encoding.h"
#include "reference/encoding/hash_encoding.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"

using namespace vknerf;
using ref::HashGridConfig;

namespace {

class HashPositionGradient : public test::GpuTest {};

// Dense and hashed levels, F = 1, 2, 4 and 8, resolutions that are and are not powers of two.
const HashGridConfig kConfigs[] = {{6, 2, 12, 4, 2.0}, {3, 1, 6, 3, 1.37}, {2, 4, 8, 8, 3.0}, {3, 8, 7, 2, 2.0}};

// Points with 12 fractional bits of u = (p + 1) / 2: u * res is exact in float for every level, so
// the device's cell and in-cell position w equal the reference's exactly, and what differs is the
// rounding of the products and sums alone. None lies on a cell face at any level (w = 0), where the
// feature has a kink and a central difference would straddle two cells; w >= 1/4096 * res there,
// far wider than the difference step. Every 7th point lies outside the box on one axis, where the
// forward clamps p and the gradient along that axis is 0.
std::vector<float> interiorPositions(const HashGridConfig& c, uint32_t count, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_int_distribution<int> k(1, 4095);
  std::vector<float> v;
  while (v.size() < 4 * size_t(count)) {
    float p[3];
    bool onFace = false;
    for (int a = 0; a < 3; ++a) {
      const int u = k(gen);
      p[a] = float(u) / 2048.0f - 1.0f;
      for (uint32_t l = 0; l < c.levels; ++l) onFace |= (uint64_t(u) * ref::hashGridResolution(c, l)) % 4096 == 0;
    }
    if (onFace) continue;
    const size_t i = v.size() / 4;
    if (i % 7 == 3) p[i % 3] = (i & 1) ? 1.5f : -2.0f;
    v.insert(v.end(), {p[0], p[1], p[2], 0.0f});
  }
  return v;
}

// Both ways of computing it: on its own, or in the table's backward pass (whose table gradient must
// then be the plain backward's: checked in FromTheBackwardPassLeavesTheTableGradient).
enum class Way { Alone, InBackward };
const char* nameOf(Way w) { return w == Way::Alone ? "Alone" : "InBackward"; }
void PrintTo(Way w, std::ostream* os) { *os << nameOf(w); }

class HashPositionGradientWays : public HashPositionGradient, public testing::WithParamInterface<Way> {};

// The device's dL/dp (vec4 per row in `got`) against central differences, step h, of
// S(p) = dF_r . features(p) from the double reference, within `tol`, for every row and axis.
void expectMatchesCentralDifferences(const HashGridConfig& c, const std::vector<float>& table, const std::vector<float>& dF,
                                     uint32_t stride, const std::vector<float>& pos, const std::vector<float>& got,
                                     double h, double tol) {
  const std::vector<double> tableD(table.begin(), table.end());
  const uint32_t D = c.levels * c.featuresPerLevel, n = uint32_t(pos.size() / 4);
  for (uint32_t r = 0; r < n; ++r) {
    auto S = [&](const double* p) {
      const auto f = ref::hashEncoding<double>(c, tableD.data(), p);
      double s = 0;
      for (uint32_t j = 0; j < D; ++j) s += double(dF[size_t(r) * stride + j]) * f[j];
      return s;
    };
    for (int a = 0; a < 3; ++a) {
      double up[3] = {pos[4 * r], pos[4 * r + 1], pos[4 * r + 2]}, down[3] = {up[0], up[1], up[2]};
      up[a] += h, down[a] -= h;
      const double want = (S(up) - S(down)) / (2 * h);
      ASSERT_TRUE(test::near(got[4 * r + a], want, 0, tol))
          << "levels " << c.levels << " F " << c.featuresPerLevel << " contraction " << c.contraction << " row " << r
          << " axis " << a << ": " << got[4 * r + a] << " vs " << want << " (tol " << tol << ")";
    }
  }
}

TEST_P(HashPositionGradientWays, MatchesFiniteDifferencesOfTheReference) {
  for (const HashGridConfig& c : kConfigs) {
    nerf::HashEncoding enc(ctx(), c);
    const uint32_t n = 300, D = enc.outputDims(), stride = enc.paddedDims() + 4;
    std::mt19937 gen(c.levels * 10 + c.featuresPerLevel);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<float> table(enc.parameterCount()), dF(size_t(n) * stride, 0.0f);
    for (auto& x : table) x = u(gen);
    for (uint32_t r = 0; r < n; ++r)
      for (uint32_t j = 0; j < D; ++j) dF[size_t(r) * stride + j] = u(gen);
    // A sample behind a ray's cut has dL/dfeatures = 0: its gradient must be exactly 0.
    for (uint32_t j = 0; j < D; ++j) dF[size_t(n - 1) * stride + j] = 0.0f;
    const auto pos = interiorPositions(c, n, 7);
    auto pb = gpu::Buffer::of(ctx(), pos), tb = gpu::Buffer::of(ctx(), table), db = gpu::Buffer::of(ctx(), dF);
    auto out = gpu::Buffer::of(ctx(), std::vector<float>(size_t(n) * 4, 12345.0f));
    auto grads = gpu::Buffer::zeros(ctx(), enc.parameterCount() * 4);
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      if (GetParam() == Way::Alone) enc.recordPositionGradient(rec, {n, pb, db, stride, 0}, tb, out);
      else enc.recordBackward(rec, {n, pb, db, stride, 0}, grads, nerf::PositionGradientTarget{tb, out});
    });
    const auto got = out.download<float>();

    double resSum = 0;
    for (uint32_t l = 0; l < c.levels; ++l) resSum += ref::hashGridResolution(c, l);
    // Per level the device sums 8 corners of F products (|dF|, |table| <= 1) times weight
    // products, all exact inputs: about 20 roundings of terms up to F * res / 2 each, 8 corners:
    // 80 F res 2^-24 per level, summed over levels. The difference quotient is exact up to
    // rounding of S (trilinear within a cell): |S| <= L F, 1e-15 relative over h = 1e-5.
    const double tol = 80.0 * c.featuresPerLevel * resSum * std::ldexp(1.0, -24) + 1e-8;
    expectMatchesCentralDifferences(c, table, dF, stride, pos, got, 1e-5, tol);
    if (HasFatalFailure()) return;
    for (int a = 0; a < 3; ++a) EXPECT_EQ(got[4 * (n - 1) + a], 0.0f);
  }
}

// Through the contraction (S = 4 over kConfigs[0]): the chain rule of hashGridContractGradient
// against central differences of the reference, which contracts in double. Points are drawn over the
// whole box and kept away from every kink the step h could straddle: a cell face of any level in
// the contracted grid, the inner cube's faces (m = 1) and the planes where the largest axis changes.
TEST_P(HashPositionGradientWays, MatchesFiniteDifferencesThroughTheContraction) {
  HashGridConfig c = kConfigs[0];
  c.contraction = 4;
  nerf::HashEncoding enc(ctx(), c);
  const uint32_t n = 300, D = enc.outputDims(), stride = enc.paddedDims();
  std::mt19937 gen(17);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> table(enc.parameterCount()), dF(size_t(n) * stride, 0.0f), pos;
  for (auto& x : table) x = u(gen);
  for (auto& x : dF) x = u(gen);
  const double h = 1e-5, margin = 1e-3;
  while (pos.size() < 4 * size_t(n)) {
    const float p[3] = {u(gen), u(gen), u(gen)};
    const double pd[3] = {p[0], p[1], p[2]};
    double a[3];
    for (int k = 0; k < 3; ++k) a[k] = std::fabs(4.0 * pd[k]);
    std::sort(a, a + 3);
    bool nearKink = std::fabs(a[2] - 1.0) < margin || a[2] - a[1] < margin;
    const auto q = ref::hashGridContract(pd, 4);
    for (uint32_t l = 0; l < c.levels; ++l)
      for (int k = 0; k < 3; ++k) {
        const double x = (q[k] + 1) * 0.5 * ref::hashGridResolution(c, l);
        nearKink |= std::fabs(x - std::round(x)) < 3 * margin;  // h moves x by up to h S res / 4 = 1.3e-3
      }
    if (!nearKink) pos.insert(pos.end(), {p[0], p[1], p[2], 0.0f});
  }
  auto pb = gpu::Buffer::of(ctx(), pos), tb = gpu::Buffer::of(ctx(), table), db = gpu::Buffer::of(ctx(), dF);
  auto out = gpu::Buffer::of(ctx(), std::vector<float>(size_t(n) * 4, 12345.0f));
  auto grads = gpu::Buffer::zeros(ctx(), enc.parameterCount() * 4);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    if (GetParam() == Way::Alone) enc.recordPositionGradient(rec, {n, pb, db, stride, 0}, tb, out);
    else enc.recordBackward(rec, {n, pb, db, stride, 0}, grads, nerf::PositionGradientTarget{tb, out});
  });
  const auto got = out.download<float>();
  double resSum = 0;
  for (uint32_t l = 0; l < c.levels; ++l) resSum += ref::hashGridResolution(c, l);
  // MatchesFiniteDifferencesOfTheReference's bound on dL/dp' times the Jacobian's norm, at most
  // S / 2 (2/m - 1/m^2 <= 1, the radial term adds at most 2 more): 3 S / 2; plus the contracted
  // position's own rounding (4 roundings of |p'| <= 1), which moves w by 2 res 2^-24 and the
  // gradient, 2 F max|t dF| res / 2 per unit of w, by F res^2 2^-24 per level; and the quotient's
  // truncation, second derivatives of the contraction (<= 6 S^2 / m^3) times h^2.
  double tol = 1.5 * 4 * (80.0 * c.featuresPerLevel * resSum * std::ldexp(1.0, -24)) + 1e-6;
  for (uint32_t l = 0; l < c.levels; ++l) {
    const double r = ref::hashGridResolution(c, l);
    tol += 1.5 * 4 * c.featuresPerLevel * r * r * std::ldexp(1.0, -24);
  }
  expectMatchesCentralDifferences(c, table, dF, stride, pos, got, h, tol);
}

TEST_P(HashPositionGradientWays, RowLimitLeavesLaterRowsUntouched) {
  const HashGridConfig& c = kConfigs[0];
  nerf::HashEncoding enc(ctx(), c);
  const uint32_t n = 130, stride = enc.paddedDims();
  auto pb = gpu::Buffer::of(ctx(), interiorPositions(c, n, 3));
  auto tb = gpu::Buffer::of(ctx(), std::vector<float>(enc.parameterCount(), 0.5f));
  auto db = gpu::Buffer::of(ctx(), std::vector<float>(size_t(n) * stride, 1.0f));
  auto limit = gpu::Buffer::of(ctx(), std::vector<uint32_t>{70});
  auto out = gpu::Buffer::of(ctx(), std::vector<float>(size_t(n) * 4, 12345.0f));
  auto grads = gpu::Buffer::zeros(ctx(), enc.parameterCount() * 4);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    const nerf::EncodedRows rows{n, pb, db, stride, 0, gpu::BufferRange(limit)};
    if (GetParam() == Way::Alone) enc.recordPositionGradient(rec, rows, tb, out);
    else enc.recordBackward(rec, rows, grads, nerf::PositionGradientTarget{tb, out});
  });
  const auto got = out.download<float>();
  for (uint32_t r = 0; r < n; ++r) EXPECT_EQ(got[4 * r + 3] == 12345.0f, r >= 70) << "row " << r;
}

INSTANTIATE_TEST_SUITE_P(Ways, HashPositionGradientWays, testing::Values(Way::Alone, Way::InBackward),
                         [](const testing::TestParamInfo<Way>& info) { return std::string(nameOf(info.param)); });

// The backward that also writes dL/dp adds the same table gradient as the plain one, and the same
// dL/dp as the kernel alone, in every backward mode. The table gradient sums each entry's terms
// with float atomics in an order neither run fixes: a relative 1e-5 of the entry's sum of
// magnitudes bounds the difference (a few dozen terms an entry here, 2^-24 each), which a term
// missing or doubled exceeds. dL/dp is each row's own fixed sequence of operations: bit for bit.
TEST_F(HashPositionGradient, FromTheBackwardPassLeavesTheTableGradient) {
  const HashGridConfig& c = kConfigs[0];
  for (const auto mode : {nerf::HashBackwardMode::Atomic, nerf::HashBackwardMode::SubgroupMerged,
                          nerf::HashBackwardMode::SortReduce, nerf::HashBackwardMode::CompareSwap}) {
    SCOPED_TRACE(testing::Message() << "mode " << uint32_t(mode));
    if (!test::deviceRuns(mode)) continue;
    nerf::HashEncoding enc(ctx(), c, mode);
    const uint32_t n = 200, stride = enc.paddedDims();
    std::mt19937 gen(3);
    std::uniform_real_distribution<float> u(-1, 1);
    std::vector<float> table(enc.parameterCount()), dF(size_t(n) * stride);
    for (auto& x : table) x = u(gen);
    for (auto& x : dF) x = u(gen);
    std::vector<float> absDF(dF.size());
    for (size_t i = 0; i < dF.size(); ++i) absDF[i] = std::fabs(dF[i]);
    const auto pos = interiorPositions(c, n, 11);
    auto pb = gpu::Buffer::of(ctx(), pos), tb = gpu::Buffer::of(ctx(), table), db = gpu::Buffer::of(ctx(), dF),
         absDb = gpu::Buffer::of(ctx(), absDF);
    auto run = [&](const gpu::Buffer& dFeatures, bool fused, std::vector<float>* dP) {
      auto grads = gpu::Buffer::zeros(ctx(), enc.parameterCount() * 4);
      auto out = gpu::Buffer::of(ctx(), std::vector<float>(size_t(n) * 4, 12345.0f));
      test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
        const nerf::EncodedRows rows{n, pb, dFeatures, stride, 0};
        if (fused) enc.recordBackward(rec, rows, grads, nerf::PositionGradientTarget{tb, out});
        else enc.recordBackward(rec, rows, grads), enc.recordPositionGradient(rec, rows, tb, out);
      });
      if (dP) *dP = out.download<float>();
      return grads.download<float>(enc.parameterCount());
    };
    std::vector<float> dPPlain, dPFused;
    const auto plain = run(db, false, &dPPlain), fused = run(db, true, &dPFused), scale = run(absDb, false, nullptr);
    for (size_t i = 0; i < plain.size(); ++i)
      ASSERT_TRUE(test::near(fused[i], plain[i], 0, 1e-5 * scale[i] + 1e-30)) << "entry " << i;
    ASSERT_EQ(dPFused, dPPlain);
  }
}

}  // namespace

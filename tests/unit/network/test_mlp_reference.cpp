// The MLP CPU reference (tests/reference/network/mlp.h) on its own: gradients against central finite
// differences in double, the NeRF structure (sigma never sees the direction), initialisation.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "reference/network/mlp.h"
#include "reference/rng.h"

using namespace vknerf;

namespace {

std::vector<double> randomVector(size_t n, uint32_t seed, double scale) {
  std::vector<double> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = scale * (2.0 * ref::rng01(seed, uint32_t(i), 7) - 1.0);
  return v;
}

std::vector<double> toDouble(const std::vector<float>& v) { return {v.begin(), v.end()}; }

// L = sum_i dOut_i out_i over a few samples, so dL/dparams = the backward pass seeded with dOut.
double nerfLoss(const ref::NerfShape& s, const std::vector<double>& p, const std::vector<double>& pos,
                const std::vector<double>& dir, const std::vector<double>& dOut, int samples) {
  double L = 0;
  for (int i = 0; i < samples; ++i) {
    auto fw = ref::nerfForward<double>(s, p, &pos[i * s.posDims], &dir[i * s.dirDims]);
    for (int c = 0; c < 4; ++c) L += dOut[4 * i + c] * fw.out[c];
  }
  return L;
}

// Central differences with step h = 1e-5 have truncation error ~h^2 |f'''| ~ 1e-10 and rounding
// error ~eps |L| / h ~ 1e-11 for these O(1) losses; a ReLU kink inside [x-h, x+h] is improbable
// with random inputs. Tolerance 1e-6 absolute + 1e-6 relative leaves a wide margin while any
// wrong term of an O(0.01..1) gradient still fails.
constexpr double kFdStep = 1e-5, kFdTol = 1e-6;

class MlpReference : public ::testing::TestWithParam<DensityActivation> {};

// The network's gradients (parameters and gamma(x)) against central differences of its loss.
void expectNerfGradientsMatchFiniteDifferences(const ref::NerfShape& s);

}  // namespace

TEST_P(MlpReference, NerfGradientsMatchFiniteDifferences) {
  expectNerfGradientsMatchFiniteDifferences(ref::NerfShape::make(3, 8, 1, 5, 3, GetParam()));
}

// A feature narrower than the trunk (the fast model's shape): the colour layer reads f[0, 4), the
// density f[4].
TEST(MlpReferenceNarrowFeature, GradientsMatchFiniteDifferences) {
  const auto s = ref::NerfShape::make(2, 8, 0, 5, 3, DensityActivation::TruncExp, 4);
  EXPECT_EQ(s.feature().n, 5u);
  EXPECT_EQ(s.colour().ka, 4u);
  expectNerfGradientsMatchFiniteDifferences(s);
}

TEST(MlpReferenceNarrowFeature, WidthsThatCannotWorkAreErrors) {
  EXPECT_THROW(ref::NerfShape::make(2, 8, 0, 5, 3, DensityActivation::Relu, 6), std::invalid_argument);   // not 4k
  EXPECT_THROW(ref::NerfShape::make(2, 8, 0, 5, 3, DensityActivation::Relu, 12), std::invalid_argument);  // > width
  EXPECT_EQ(ref::NerfShape::make(2, 8, 0, 5, 3, DensityActivation::Relu, 0).featureWidth, 8u);  // 0: the width
}

namespace {

void expectNerfGradientsMatchFiniteDifferences(const ref::NerfShape& s) {
  auto p = toDouble(ref::initialParameters(s.layers, s.total, 11));
  // Larger-than-init biases keep ReLUs away from all-dead so the gradient is not trivially zero.
  for (auto& l : s.layers)
    for (uint32_t n = 0; n < l.n; ++n) p[l.biasOffset() + n] += 0.3;
  const int samples = 3;
  auto pos = randomVector(samples * s.posDims, 1, 1.0), dir = randomVector(samples * s.dirDims, 2, 1.0);
  auto dOut = randomVector(samples * 4, 3, 1.0);

  std::vector<double> g(s.total, 0.0), dPos(samples * s.posDims), dDir(samples * s.dirDims);
  for (int i = 0; i < samples; ++i) {
    auto fw = ref::nerfForward<double>(s, p, &pos[i * s.posDims], &dir[i * s.dirDims]);
    std::array<double, 4> d{dOut[4 * i], dOut[4 * i + 1], dOut[4 * i + 2], dOut[4 * i + 3]};
    ref::nerfBackward(s, p, &pos[i * s.posDims], &dir[i * s.dirDims], fw, d, g, &dPos[i * s.posDims], &dDir[i * s.dirDims]);
  }
  int nonzero = 0;
  for (size_t i = 0; i < s.total; ++i) {
    auto q = p;
    q[i] += kFdStep;
    double up = nerfLoss(s, q, pos, dir, dOut, samples);
    q[i] -= 2 * kFdStep;
    double down = nerfLoss(s, q, pos, dir, dOut, samples);
    double fd = (up - down) / (2 * kFdStep);
    EXPECT_NEAR(g[i], fd, kFdTol + kFdTol * std::fabs(fd)) << "parameter " << i;
    nonzero += g[i] != 0;
  }
  EXPECT_GT(nonzero, int(s.total) / 2);  // padding and dead units are zero, most are not
  for (size_t i = 0; i < pos.size(); ++i) {
    auto q = pos;
    q[i] += kFdStep;
    double up = nerfLoss(s, p, q, dir, dOut, samples);
    q[i] -= 2 * kFdStep;
    double down = nerfLoss(s, p, q, dir, dOut, samples);
    double fd = (up - down) / (2 * kFdStep);
    EXPECT_NEAR(dPos[i], fd, kFdTol + kFdTol * std::fabs(fd)) << "gamma(x) component " << i;
  }
  // The direction input (and what is learned beside it, an appearance vector): through the colour
  // layer alone. A wrong gradient here would train the vectors the wrong way.
  int dirNonzero = 0;
  for (size_t i = 0; i < dir.size(); ++i) {
    auto q = dir;
    q[i] += kFdStep;
    double up = nerfLoss(s, p, pos, q, dOut, samples);
    q[i] -= 2 * kFdStep;
    double down = nerfLoss(s, p, pos, q, dOut, samples);
    double fd = (up - down) / (2 * kFdStep);
    EXPECT_NEAR(dDir[i], fd, kFdTol + kFdTol * std::fabs(fd)) << "direction component " << i;
    dirNonzero += dDir[i] != 0;
  }
  EXPECT_GT(dirNonzero, 0);
}

}  // namespace

INSTANTIATE_TEST_SUITE_P(MlpDensity, MlpReference,
                         ::testing::Values(DensityActivation::Relu, DensityActivation::TruncExp,
                                           DensityActivation::Softplus));

TEST(MlpReferenceDense, GradientsMatchFiniteDifferences) {
  auto s = ref::DenseMlpShape::make(5, 8, 2, 3);
  auto p = toDouble(ref::initialParameters(s.layers, s.total, 5));
  for (auto& l : s.layers)
    for (uint32_t n = 0; n < l.n; ++n) p[l.biasOffset() + n] += 0.2;
  auto in = randomVector(5, 9, 1.0), dOut = randomVector(3, 10, 1.0);
  auto loss = [&](const std::vector<double>& q, const std::vector<double>& x) {
    auto acts = ref::denseMlpForward<double>(s, q, x.data());
    return dOut[0] * acts.back()[0] + dOut[1] * acts.back()[1] + dOut[2] * acts.back()[2];
  };
  std::vector<double> g(s.total, 0.0), dIn(5);
  ref::denseMlpBackward(s, p, in.data(), ref::denseMlpForward<double>(s, p, in.data()), dOut.data(), g, dIn.data());
  for (size_t i = 0; i < s.total; ++i) {
    auto q = p;
    q[i] += kFdStep;
    double up = loss(q, in);
    q[i] -= 2 * kFdStep;
    double fd = (up - loss(q, in)) / (2 * kFdStep);
    EXPECT_NEAR(g[i], fd, kFdTol + kFdTol * std::fabs(fd)) << "parameter " << i;
  }
  for (size_t i = 0; i < in.size(); ++i) {
    auto x = in;
    x[i] += kFdStep;
    double up = loss(p, x);
    x[i] -= 2 * kFdStep;
    double fd = (up - loss(p, x)) / (2 * kFdStep);
    EXPECT_NEAR(dIn[i], fd, kFdTol + kFdTol * std::fabs(fd)) << "input " << i;
  }
}

TEST(MlpReferenceNerf, SigmaNeverDependsOnDirection) {
  auto s = ref::NerfShape::make(4, 16, 2, 63, 27, DensityActivation::Softplus);
  auto p = ref::initialParameters(s.layers, s.total, 3);
  auto pos = randomVector(63, 4, 1.0);
  auto dirA = randomVector(27, 5, 1.0), dirB = randomVector(27, 6, 1.0);
  auto a = ref::nerfForward<double>(s, p, pos.data(), dirA.data());
  auto b = ref::nerfForward<double>(s, p, pos.data(), dirB.data());
  EXPECT_EQ(a.out[3], b.out[3]);
  EXPECT_NE(a.out[0], b.out[0]);  // while the colour does depend on it
  // and the gradient of sigma reaches no direction input
  std::vector<double> g(s.total, 0.0), dDir(27, 1.0);
  ref::nerfBackward(s, p, pos.data(), dirA.data(), a, {0, 0, 0, 1}, g, (double*)nullptr, dDir.data());
  for (double v : dDir) EXPECT_EQ(v, 0.0);
}

TEST(MlpReferenceNerf, LayoutAndInitialisation) {
  auto s = ref::NerfShape::make(8, 256, 5, 63, 27, DensityActivation::Relu);
  // trunk: 64x256 + 7 x 256x256 (+64 rows at the skip), feature 256 x 260, colour (256+28) x 128,
  // head 128 x 4; each with a bias row.
  uint64_t expect = (64 + 1) * 256ull + 7 * (256 + 1) * 256ull + 64 * 256ull + (256 + 1) * 260ull +
                    (256 + 28 + 1) * 128ull + (128 + 1) * 4ull;
  EXPECT_EQ(s.total, expect);
  auto p = ref::initialParameters(s.layers, s.total, 42);
  EXPECT_EQ(p, ref::initialParameters(s.layers, s.total, 42));
  EXPECT_NE(p, ref::initialParameters(s.layers, s.total, 43));
  for (const auto& l : s.layers) {
    double bound = 1.0 / std::sqrt(double(l.ka + l.kb));
    double maxAbs = 0;
    for (uint32_t k = 0; k < l.k4(); ++k)
      for (uint32_t n = 0; n < l.n4(); ++n) {
        float w = p[l.offset + uint64_t(k) * l.n4() + n];
        bool pad = n >= l.n || (k < l.ka4() ? k >= l.ka : k - l.ka4() >= l.kb);
        if (pad) EXPECT_EQ(w, 0.0f);
        EXPECT_LE(std::fabs(w), bound);
        maxAbs = std::max(maxAbs, double(std::fabs(w)));
      }
    EXPECT_GT(maxAbs, 0.9 * bound);  // the draws span the PyTorch range
  }
}

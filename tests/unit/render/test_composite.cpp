// composite_forward.comp and composite_backward.comp against the CPU reference
// (tests/reference/render/composite.h), the reference's gradients against finite differences, and the
// numerically hard rays (opaque, faint, duplicate, open-ended, empty, very long).
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "nerf/render/composite.h"
#include "reference/render/composite.h"
#include "reference/render/distortion_loss.h"

using namespace vknerf;

namespace {

constexpr double kU = 1.0 / 16777216.0;  // float unit roundoff, 2^-24
constexpr float kInf = std::numeric_limits<float>::infinity();

// A batch of rays in the GPU layouts, with the upstream gradients the backward pass consumes.
struct Batch {
  uint32_t samplesPerRay = 0;          // 0: packed through `offsets`
  std::vector<uint32_t> offsets{0};    // numRays + 1, kept for both layouts (the CPU side walks it)
  std::vector<float> samples, field;   // 2 and 4 floats per sample
  std::array<float, 3> bg{0, 0, 0};
  std::vector<float> perRayBg;         // 4 per ray; empty: `bg` for every ray
  std::vector<float> dColor, dDepth;   // 4 and 1 per ray
  std::vector<float> rays;             // (o, t_near), (d, t_far) per ray: the distortion loss's near and far

  uint32_t numRays() const { return uint32_t(offsets.size() - 1); }
  uint32_t begin(uint32_t r) const { return offsets[r]; }
  uint32_t count(uint32_t r) const { return offsets[r + 1] - offsets[r]; }
  void addRay(std::span<const float> s, std::span<const float> f, std::array<float, 3> background = {0, 0, 0},
              std::array<float, 4> dc = {0, 0, 0, 0}, float dd = 0) {
    samples.insert(samples.end(), s.begin(), s.end());
    field.insert(field.end(), f.begin(), f.end());
    offsets.push_back(uint32_t(samples.size() / 2));
    perRayBg.insert(perRayBg.end(), {background[0], background[1], background[2], 0});
    dColor.insert(dColor.end(), dc.begin(), dc.end());
    dDepth.push_back(dd);
    // The ray's near a little in front of its first sample, its far a little behind its last.
    const float tNear = s.empty() ? 0.0f : 0.9f * s[0], tFar = s.empty() ? 1.0f : s[s.size() - 2] + s.back() + 0.25f;
    rays.insert(rays.end(), {0, 0, 0, tNear, 0, 0, -1, tFar});
  }
  ref::DistortionRay<double> distortionRay(uint32_t r, const ref::MarchSpacing<double>& spacing, bool farField = false) const {
    return {spacing, rays[8 * r + 3], rays[8 * r + 7], farField};
  }
  std::array<double, 3> background(uint32_t r) const {
    if (perRayBg.empty()) return {bg[0], bg[1], bg[2]};
    return {perRayBg[4 * r], perRayBg[4 * r + 1], perRayBg[4 * r + 2]};
  }
  std::vector<double> raySamples(uint32_t r) const {
    return {samples.begin() + 2 * begin(r), samples.begin() + 2 * (begin(r) + count(r))};
  }
  std::vector<double> rayField(uint32_t r) const {
    return {field.begin() + 4 * begin(r), field.begin() + 4 * (begin(r) + count(r))};
  }
};

struct GpuResult {
  std::vector<float> color, depth, weights, dField;
  std::vector<float> termValues;  // vec4 per ray: the loss terms the backward added, weighted
};

// The distortion loss's weight per ray, the march spacing it measures distances in, and whether
// the far field's weight counts as its last interval.
struct Distortion {
  double weight = 0;
  ref::MarchSpacing<double> spacing;
  bool farField = false;
};
// Cone steps from 0.01 to 0.08 at 1/64: t1 = 0.64 and t2 = 5.12 put all three pieces of the spacing
// inside the random rays' [0.5, ~12].
constexpr ref::MarchSpacing<double> kConeSpacing{1.0 / 64, 0.01, 0.08};

// Forward then backward, recorded in one command buffer as a training step would be.
GpuResult runGpu(Context& ctx, const Batch& b, const Distortion& distortion = {}) {
  uint32_t rays = b.numRays(), samples = uint32_t(b.samples.size() / 2);
  auto bytes = [](size_t n) { return std::max<size_t>(n, 4) * 4; };  // empty arrays still bind
  gpu::Buffer offsets(ctx, bytes(b.offsets.size())), sampleBuf(ctx, bytes(b.samples.size())),
      fieldBuf(ctx, bytes(b.field.size())), bgBuf(ctx, bytes(b.perRayBg.size())), dColor(ctx, bytes(b.dColor.size())),
      dDepth(ctx, bytes(b.dDepth.size())), color(ctx, bytes(4 * rays)), depth(ctx, bytes(rays)),
      weights(ctx, bytes(samples)), dField(ctx, bytes(4 * samples)), rayBuf(ctx, bytes(b.rays.size())),
      termValues(ctx, bytes(4 * rays));
  offsets.upload(b.offsets);
  rayBuf.upload(b.rays);
  sampleBuf.upload(b.samples);
  fieldBuf.upload(b.field);
  bgBuf.upload(b.perRayBg);
  dColor.upload(b.dColor);
  dDepth.upload(b.dDepth);
  // NaN sentinels: any output the kernels fail to write shows up as a non-finite value.
  std::vector<float> nan(4 * std::max<size_t>(samples, rays), std::numeric_limits<float>::quiet_NaN());
  weights.upload(nan.data(), samples * 4);
  dField.upload(nan.data(), samples * 16);
  color.upload(nan.data(), rays * 16);
  depth.upload(nan.data(), rays * 4);
  termValues.upload(nan.data(), rays * 16);

  nerf::Compositor comp(ctx);
  nerf::CompositeInputs in{rays, b.samplesPerRay, b.samplesPerRay ? gpu::BufferRange() : gpu::BufferRange(offsets),
                           sampleBuf, fieldBuf, b.bg};
  if (!b.perRayBg.empty()) in.perRayBackground = gpu::BufferRange(bgBuf);
  const nerf::DistortionLoss loss{float(distortion.weight), float(distortion.spacing.coneAngle),
                                  float(distortion.spacing.dtMin), float(distortion.spacing.dtMax), rayBuf,
                                  distortion.farField};
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    comp.recordForward(rec, in, {color, depth, weights});
    comp.recordBackward(rec, in, {dColor, dDepth, dField, {loss}, gpu::BufferRange(termValues)});
  });
  return {color.download<float>(4 * rays), depth.download<float>(rays), weights.download<float>(samples),
          dField.download<float>(4 * samples), termValues.download<float>(4 * rays)};
}

// Error model of the float kernels against the double reference, used for every tolerance below.
// The prefix sum S_i of i optical depths is off by at most i*u*S_i (each addition rounds by
// u * partial sum), a relative error of T_i = exp(-S_i); exp, the alpha series and the products
// add a few ulps (8u covers them). The back-to-front mixes Q carry about 4u per remaining sample in
// absolute terms (colours and backgrounds are in [0, 1]). All bounds get a factor 4 of headroom;
// they are worst cases, the measured errors are far below them.
struct RayTolerance {
  std::vector<double> eps;  // eps[i]: relative error bound of T_i, i = 0..n (eps[n]: T_final)
  std::vector<double> transmittance;  // double T_i, i = 0..n
};

RayTolerance rayTolerance(std::span<const double> s, std::span<const double> f) {
  size_t n = s.size() / 2;
  RayTolerance tol;
  double prefix = 0;
  for (size_t i = 0; i <= n; ++i) {
    tol.eps.push_back(double(i) * kU * prefix + 8 * kU);
    tol.transmittance.push_back(std::exp(-prefix));
    if (i < n) prefix += ref::opticalDepth(f[4 * i + 3], s[2 * i + 1]);
  }
  return tol;
}

// Compares ray r of the GPU result with the double reference; returns false on the first mismatch.
::testing::AssertionResult rayMatches(const GpuResult& g, const Batch& b, uint32_t r, const Distortion& distortion = {}) {
  auto s = b.raySamples(r), f = b.rayField(r);
  auto bg = b.background(r);
  size_t n = s.size() / 2, first = b.begin(r);
  auto fwd = ref::compositeForward<double>(s, f, bg);
  std::array<double, 4> dc = {b.dColor[4 * r], b.dColor[4 * r + 1], b.dColor[4 * r + 2], b.dColor[4 * r + 3]};
  double dd = b.dDepth[r];
  const auto distortionRay = b.distortionRay(r, distortion.spacing, distortion.farField);
  auto bwd = ref::compositeBackward<double>(s, f, bg, dc, dd, distortion.weight, distortionRay);
  auto tol = rayTolerance(s, f);
  double tMax = 0;
  for (size_t i = 0; i < n; ++i) tMax = std::max(tMax, std::fabs(s[2 * i]));
  const double accum = 4 * kU * double(n + 1);  // rounding of the running sums themselves

  auto fail = [&](const char* what, size_t i, double gpu, double want, double bound) {
    return ::testing::AssertionFailure() << "ray " << r << " " << what << "[" << i << "]: gpu " << gpu << " ref "
                                         << want << " (|err| " << std::fabs(gpu - want) << " > " << bound << ")";
  };
  auto check = [](const char*, size_t, double gpu, double want, double bound) {
    return std::isfinite(gpu) && std::fabs(gpu - want) <= 4 * bound;
  };

  // Colour and depth: sum_i |dw_i| <= sum_i w_i eps_i, plus the escaping light's T_final eps_n.
  double errC = accum + tol.transmittance[n] * tol.eps[n], errD = accum * tMax;
  for (size_t i = 0; i < n; ++i) {
    errC += fwd.weights[i] * tol.eps[i];
    errD += fwd.weights[i] * tol.eps[i] * std::fabs(s[2 * i]);
  }
  for (int k = 0; k < 3; ++k)
    if (!check("color", k, g.color[4 * r + k], fwd.rgb[k], errC)) return fail("color", k, g.color[4 * r + k], fwd.rgb[k], 4 * errC);
  // Opacity 1 - exp(-S) moves by T_final * dS <= opacity * (n u + 8u) (S e^-S <= 1 - e^-S).
  double errO = fwd.opacity * (double(n) * kU + 8 * kU);
  if (!check("opacity", 0, g.color[4 * r + 3], fwd.opacity, errO)) return fail("opacity", 0, g.color[4 * r + 3], fwd.opacity, 4 * errO);
  if (!check("depth", 0, g.depth[r], fwd.depth, errD)) return fail("depth", 0, g.depth[r], fwd.depth, 4 * errD);

  // Backward: |inner_i| <= G with G = |dC|_1 + |dD| tMax (|c - Q| <= 1, |t - Qd| <= tMax); its error
  // is T_{i+1} (G eps_{i+1} + G 4u (n - i)) plus the opacity term's T_final |dO| eps_n.
  double G = std::fabs(dc[0]) + std::fabs(dc[1]) + std::fabs(dc[2]) + std::fabs(dd) * tMax;
  // The distortion loss's part: dL/dw_i sums four running sums of n terms each at most M (W, W' <= 1;
  // |S|, |S'| <= M) in the O(n) form, each off by n u M, plus the weights' own errors sum_j w_j eps_j
  // times 2M; D_k sums n products of such. M = 1 + the largest g(t) / (g(far) - g(near)): the kernel
  // forms m and l as differences of march coordinates g, each rounded relative to g itself (a few
  // u: log, divisions), so that ratio scales their absolute error. So its error in dL/dsigma_k is
  // below delta_k * weight * M * (16 n u + 4 sum_j w_j eps_j) * 2 (T_{k+1} + D's sum).
  double errDistortion = 0;
  if (distortion.weight > 0) {
    const double span = ref::marchCoordinate(distortionRay.tFar, distortion.spacing) -
                        ref::marchCoordinate(distortionRay.tNear, distortion.spacing);
    double M = 1, weightErr = 0;
    for (size_t i = 0; i < n; ++i) {
      M = std::max(M, ref::marchCoordinate(s[2 * i] + s[2 * i + 1], distortion.spacing) / span + 1);
      weightErr += fwd.weights[i] * tol.eps[i];
    }
    errDistortion = distortion.weight * M * (16 * double(n) * kU + 4 * weightErr) * 4;
    // The far field's part is of the same kind: 2 T_final |1 - m_i| in dL/dw_i (T_final off by
    // T_final eps_n, |1 - m| <= M) and 2 A T_final in every dL/dsigma_k, A a running sum of n terms
    // w_i |1 - m_i| <= M: at most as large and as inexact again as the rest.
    if (distortion.farField) errDistortion *= 2;
  }
  for (size_t i = 0; i < n; ++i) {
    double w = g.weights[first + i], errW = fwd.weights[i] * tol.eps[i] + 1e-38;
    if (!check("weight", i, w, fwd.weights[i], errW)) return fail("weight", i, w, fwd.weights[i], 4 * errW);
    for (int k = 0; k < 3; ++k) {
      double errDc = std::fabs(bwd[i][k]) * tol.eps[i] + 1e-38;
      double got = g.dField[4 * (first + i) + k];
      if (!check("dColor", i, got, bwd[i][k], errDc)) return fail("dc", i, got, bwd[i][k], 4 * errDc);
    }
    double delta = s[2 * i + 1];
    double errS = delta * (tol.transmittance[i + 1] * G * (tol.eps[i + 1] + 4 * kU * double(n - i)) +
                           tol.transmittance[n] * std::fabs(dc[3]) * tol.eps[n] + errDistortion) + 1e-38;
    double got = g.dField[4 * (first + i) + 3];
    if (!check("dSigma", i, got, bwd[i][3], errS)) return fail("dsigma", i, got, bwd[i][3], 4 * errS);
  }
  return ::testing::AssertionSuccess();
}

void expectAllRaysMatch(const GpuResult& g, const Batch& b, const Distortion& distortion = {}) {
  int failures = 0;
  for (uint32_t r = 0; r < b.numRays() && failures < 5; ++r) {
    auto ok = rayMatches(g, b, r, distortion);
    EXPECT_TRUE(ok);
    failures += !ok;
  }
}

// A random ray: t from a random near bound, deltas in [0.005, 0.1), sigma log-uniform in
// [1e-3, 50) with 10% exact zeros, colours in [0, 1). Total optical depths land around 1 to 30.
void randomRay(std::mt19937& rng, uint32_t n, std::vector<float>& s, std::vector<float>& f) {
  std::uniform_real_distribution<float> u01(0, 1);
  s.clear();
  f.clear();
  float t = 0.5f + 1.5f * u01(rng);
  for (uint32_t i = 0; i < n; ++i) {
    float delta = 0.005f + 0.095f * u01(rng);
    float sigma = u01(rng) < 0.1f ? 0.0f : std::exp(std::log(1e-3f) + u01(rng) * std::log(5e4f));
    s.insert(s.end(), {t, delta});
    f.insert(f.end(), {u01(rng), u01(rng), u01(rng), sigma});
    t += delta;
  }
}

std::array<float, 4> randomDColor(std::mt19937& rng) {
  std::uniform_real_distribution<float> g(-1, 1);
  return {g(rng), g(rng), g(rng), g(rng)};
}

Batch randomBatch(uint32_t rays, uint32_t fixedN, uint32_t maxN, bool perRayBg, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0, 1), g(-1, 1);
  Batch b;
  b.samplesPerRay = fixedN;
  b.bg = {0.3f, 0.6f, 0.9f};
  std::vector<float> s, f;
  for (uint32_t r = 0; r < rays; ++r) {
    uint32_t n = fixedN ? fixedN : uint32_t(rng() % (maxN + 1));
    randomRay(rng, n, s, f);
    b.addRay(s, f, {u01(rng), u01(rng), u01(rng)}, randomDColor(rng), g(rng));
  }
  if (!perRayBg) b.perRayBg.clear();
  return b;
}

Batch singleRay(std::span<const float> s, std::span<const float> f, std::array<float, 3> bg = {0, 0, 0},
                std::array<float, 4> dc = {0.7f, -0.4f, 0.25f, 0.5f}, float dd = -0.3f) {
  Batch b;
  b.addRay(s, f, bg, dc, dd);
  b.perRayBg.clear();
  b.bg = bg;
  return b;
}

bool allFinite(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

class Composite : public test::GpuTest {};

// Seed §4.5: sigma (0.5, 2, 8), delta 0.5, red/green/blue at t = (1, 1.5, 2), black background.
const std::vector<float> kSeedSamples = {1, 0.5f, 1.5f, 0.5f, 2, 0.5f};
const std::vector<float> kSeedField = {1, 0, 0, 0.5f, 0, 1, 0, 2, 0, 0, 1, 8};
// Exercise C1: sigma (1, 2, 0.5), delta 0.5, red, green, white.
const std::vector<float> kC1Samples = {1, 0.5f, 1.5f, 0.5f, 2, 0.5f};
const std::vector<float> kC1Field = {1, 0, 0, 1, 0, 1, 0, 2, 1, 1, 1, 0.5f};

// The seed prints six decimals: half a unit in the last place, plus float rounding on the GPU.
constexpr double kPrinted = 6e-7;

}  // namespace

TEST(CompositeReference, SeedThreeSampleExample) {
  std::vector<double> s(kSeedSamples.begin(), kSeedSamples.end()), f(kSeedField.begin(), kSeedField.end());
  auto out = ref::compositeForward<double>(s, f, {0, 0, 0});
  const double w[3] = {0.221199, 0.492296, 0.281257};
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(out.weights[i], w[i], kPrinted);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.rgb[k], w[k], kPrinted);
  EXPECT_NEAR(out.opacity, 0.994752, kPrinted);
  EXPECT_NEAR(out.depth, 1.522158, kPrinted);
  EXPECT_NEAR(out.depth / out.opacity, 1.530187, kPrinted);
  auto outF = ref::compositeForward<float>(std::vector<float>(kSeedSamples), std::vector<float>(kSeedField), {0, 0, 0});
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(outF.weights[i], w[i], kPrinted);
  EXPECT_NEAR(outF.depth, 1.522158, 1e-6);
}

TEST(CompositeReference, ExerciseC1) {
  std::vector<double> s(kC1Samples.begin(), kC1Samples.end()), f(kC1Field.begin(), kC1Field.end());
  auto out = ref::compositeForward<double>(s, f, {0, 0, 0});
  const double w[3] = {0.393469, 0.383400, 0.049356};
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(out.weights[i], w[i], kPrinted);
  EXPECT_NEAR(out.opacity, 0.826226, kPrinted);
  EXPECT_NEAR(out.opacity, 1 - std::exp(-1.75), 1e-15);
  EXPECT_NEAR(out.rgb[0], w[0] + w[2], 2 * kPrinted);
  EXPECT_NEAR(out.rgb[1], w[1] + w[2], 2 * kPrinted);
  EXPECT_NEAR(out.rgb[2], w[2], kPrinted);
}

TEST_F(Composite, SeedExamplesOnShader) {
  Batch b;
  b.addRay(kSeedSamples, kSeedField, {0, 0, 0}, {1, 0, 0, 0}, 0);
  b.addRay(kC1Samples, kC1Field, {0, 0, 0}, {0, 1, 0, 0}, 0);
  b.perRayBg.clear();
  b.samplesPerRay = 3;
  auto g = runGpu(ctx(), b);
  const double w[2][3] = {{0.221199, 0.492296, 0.281257}, {0.393469, 0.383400, 0.049356}};
  for (int r = 0; r < 2; ++r)
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(g.weights[3 * r + i], w[r][i], kPrinted);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(g.color[k], w[0][k], kPrinted);
  EXPECT_NEAR(g.color[3], 0.994752, kPrinted);
  EXPECT_NEAR(g.depth[0], 1.522158, 1e-6);
  EXPECT_NEAR(g.depth[0] / g.color[3], 1.530187, 1e-6);
  EXPECT_NEAR(g.color[4 + 0], w[1][0] + w[1][2], 2 * kPrinted);
  EXPECT_NEAR(g.color[4 + 1], w[1][1] + w[1][2], 2 * kPrinted);
  EXPECT_NEAR(g.color[4 + 3], 0.826226, kPrinted);
  for (uint32_t r = 0; r < 2; ++r) EXPECT_TRUE(rayMatches(g, b, r));
}

TEST_F(Composite, MatchesReferenceFixedLayout) {
  auto b = randomBatch(256, 48, 0, true, 11);
  expectAllRaysMatch(runGpu(ctx(), b), b);
  auto c = randomBatch(70, 5, 0, false, 12);  // constant background, a partial last workgroup
  expectAllRaysMatch(runGpu(ctx(), c), c);
}

TEST_F(Composite, MatchesReferencePackedLayout) {
  auto b = randomBatch(300, 0, 96, true, 21);
  uint32_t empty = 0;
  for (uint32_t r = 0; r < b.numRays(); ++r) empty += b.count(r) == 0;
  ASSERT_GT(empty, 0u) << "the batch should include empty rays";
  expectAllRaysMatch(runGpu(ctx(), b), b);
  auto c = randomBatch(65, 0, 40, false, 22);
  expectAllRaysMatch(runGpu(ctx(), c), c);
}

// The distortion loss in the backward pass: the kernel's O(n) running sums against the reference's
// O(n^2) definition, in both layouts, with weights large enough that the loss's part of dL/dsigma
// is comparable with the colour's; in cone steps (all three pieces of the spacing) and in the
// constant step of one grid. A ray from t = 0 (near 0) starts where g(t) does.
TEST_F(Composite, MatchesReferenceWithDistortion) {
  auto b = randomBatch(200, 0, 96, true, 31);
  expectAllRaysMatch(runGpu(ctx(), b, {0.5, kConeSpacing}), b, {0.5, kConeSpacing});
  const Distortion constant{0.05, {0, 0.02, 0.02}};
  auto c = randomBatch(70, 24, 0, false, 32);
  const float t0 = c.samples[0];
  for (uint32_t i = 0; i < 24; ++i) c.samples[2 * i] -= t0;  // ray 0 from t = 0
  c.rays[3] = 0, c.rays[7] -= t0;
  expectAllRaysMatch(runGpu(ctx(), c, constant), c, constant);
  expectAllRaysMatch(runGpu(ctx(), c, {0.05, kConeSpacing}), c, {0.05, kConeSpacing});
}

// The same with the far field's weight as the loss's last interval, in both layouts and both
// spacings: its part of dL/dsigma reaches every sample of a ray through T_final.
TEST_F(Composite, MatchesReferenceWithDistortionAndFarField) {
  const Distortion cone{0.5, kConeSpacing, true}, constant{0.05, {0, 0.02, 0.02}, true};
  auto b = randomBatch(200, 0, 96, true, 33);
  expectAllRaysMatch(runGpu(ctx(), b, cone), b, cone);
  auto c = randomBatch(70, 24, 0, false, 34);
  expectAllRaysMatch(runGpu(ctx(), c, constant), c, constant);
}

// Each ray's distortion loss as the backward reports it (termValues' distortion column, for the
// loss's breakdown): its weight times ref::distortionLoss over the reference's weights, in cone
// steps and in one grid's constant step; 0 without the loss.
TEST_F(Composite, ReportsEachRaysWeightedDistortionLoss) {
  for (const Distortion& d : {Distortion{0.5, kConeSpacing}, Distortion{0.05, {0, 0.02, 0.02}}, Distortion{0, kConeSpacing},
                              Distortion{0.5, kConeSpacing, true}}) {
    SCOPED_TRACE(::testing::Message() << d.weight << (d.farField ? " with the far field" : ""));
    auto b = randomBatch(150, 0, 96, true, 41);
    const GpuResult g = runGpu(ctx(), b, d);
    const uint32_t column = nerf::rayLossColumn(nerf::DistortionLoss{});
    for (uint32_t r = 0; r < b.numRays(); ++r) {
      const auto s = b.raySamples(r), f = b.rayField(r);
      const auto fw = ref::compositeForward<double>(s, f, b.background(r));
      const auto ray = b.distortionRay(r, d.spacing, d.farField);
      const double want = d.weight * ref::distortionLoss<double>(s, fw.weights, ray);
      // The float sums run over the ray's n samples with weights off by at most eps_n relative
      // (rayTolerance) and midpoints and lengths in [0, M] off by a few ulps of M: the pairwise
      // sum (at most M, its weights summing to at most 1) is then off by M (8 n u + 4 eps_n)
      // relative to its size; a factor 4 of headroom, as every bound here.
      const auto tol = rayTolerance(s, f);
      double M = 1;
      for (size_t i = 0; i < s.size() / 2; ++i)
        M = std::max(M, ref::marchCoordinate(s[2 * i] + s[2 * i + 1], d.spacing) /
                            std::max(ref::marchCoordinate(ray.tFar, d.spacing) - ref::marchCoordinate(ray.tNear, d.spacing), 1e-30) + 1);
      const double n = double(s.size() / 2);
      // The far field's term 2 T_final sum_i w_i |1 - m_i| is one more such sum (at most 2M).
      const double bound = d.weight * M * (8 * n * kU + 4 * tol.eps.back()) * 4 * (d.farField ? 2 : 1) + 1e-30;
      ASSERT_TRUE(test::near(g.termValues[4 * r + column], want, 0, bound)) << "ray " << r << ": " << g.termValues[4 * r + column]
                                                                          << " vs " << want;
    }
  }
}

// The march coordinate g(t) = integral_0^t du / step(u): continuous where step changes piece, and
// its derivative (central differences in double, 1e-7 relative) is 1 / step in each piece.
TEST(DistortionReference, MarchCoordinateCountsSteps) {
  const ref::MarchSpacing<double> m = kConeSpacing;  // pieces meet at t1 = 0.64 and t2 = 5.12
  for (double t : {0.64, 5.12})
    EXPECT_NEAR(ref::marchCoordinate(t * (1 + 1e-12), m), ref::marchCoordinate(t * (1 - 1e-12), m), 1e-9) << t;
  for (double t : {0.1, 0.5, 0.7, 2.0, 5.0, 6.0, 40.0}) {
    const double h = 1e-6 * t, step = std::clamp(t * m.coneAngle, m.dtMin, m.dtMax);
    const double fd = (ref::marchCoordinate(t + h, m) - ref::marchCoordinate(t - h, m)) / (2 * h);
    EXPECT_NEAR(fd, 1 / step, 1e-7 / step) << t;
  }
  const ref::MarchSpacing<double> constant{0, 0.25, 0.25};
  EXPECT_DOUBLE_EQ(ref::marchCoordinate(3.0, constant), 12.0);
}

// The distortion loss's definition on hand-computed rays, in one grid's constant step over [0, 10]
// (s = t / 10): one sample alone costs w^2 l / 3; two equal weights 0.5 with midpoints at s = 0.1
// and e / 10 cost 2 * 0.25 * (e - 1) / 10 plus their own lengths; all weight in front of the other
// samples (w = 0) leaves their terms 0.
TEST(DistortionReference, LossByHand) {
  const ref::DistortionRay<double> ray{{0, 0.5, 0.5}, 0, 10};
  const double e = std::exp(1.0);
  std::vector<double> one = {0.9, 0.2}, w1 = {0.8};
  EXPECT_NEAR(ref::distortionLoss<double>(one, w1, ray), 0.64 * 0.02 / 3, 1e-15);
  std::vector<double> two = {1 - 1e-3, 2e-3, e - 1e-3, 2e-3}, w2 = {0.5, 0.5};
  const double own = 0.25 * (2e-4 + 2e-4) / 3;
  EXPECT_NEAR(ref::distortionLoss<double>(two, w2, ray), 0.5 * (e - 1) / 10 + own, 1e-12);
  std::vector<double> three = {1, 0.1, 2, 0.1, 3, 0.1}, w3 = {1, 0, 0};
  EXPECT_NEAR(ref::distortionLoss<double>(three, w3, ray),
              ref::distortionLoss<double>(std::span(three).first(2), std::span(w3).first(1), ray), 1e-15);
  // Spread weight costs more than the same weight gathered.
  std::vector<double> spread = {1, 0.1, 1.5, 0.1, 2, 0.1}, wSpread = {0.3, 0.3, 0.3}, wGathered = {0, 0.9, 0};
  EXPECT_GT(ref::distortionLoss<double>(spread, wSpread, ray), 2 * ref::distortionLoss<double>(spread, wGathered, ray));
}

// With the far field as the last interval (s = 1, length 0): one sample of weight w at midpoint m
// costs w^2 l / 3 + 2 (1 - w) w (1 - m). A ray that hands all its weight to the far field, or keeps
// it all on a surface, pays only the surface's own length; half-and-half pays for the gap between
// them, which the loss without the far field does not see.
TEST(DistortionReference, FarFieldIntervalByHand) {
  const ref::DistortionRay<double> plain{{0, 0.5, 0.5}, 0, 10}, far{{0, 0.5, 0.5}, 0, 10, true};
  const std::vector<double> one = {2.9, 0.2};  // m = 0.3, l = 0.02
  for (double w : {0.0, 0.5, 0.8, 1.0}) {
    const std::vector<double> weight = {w};
    EXPECT_NEAR(ref::distortionLoss<double>(one, weight, far), w * w * 0.02 / 3 + 2 * (1 - w) * w * 0.7, 1e-15) << w;
    EXPECT_NEAR(ref::distortionLoss<double>(one, weight, plain), w * w * 0.02 / 3, 1e-15) << w;
  }
  const std::vector<double> half = {0.5}, opaque = {1.0};
  EXPECT_GT(ref::distortionLoss<double>(one, half, far), 10 * ref::distortionLoss<double>(one, opaque, far));
  EXPECT_LT(ref::distortionLoss<double>(one, half, plain), ref::distortionLoss<double>(one, opaque, plain));
}

// The loss does not depend on the scene's units: the same weights on the same ray with every length
// (samples, near, far, the march's steps) scaled by 10 give the same loss and the same dL/dw; nor,
// with one grid's constant step, on how far in front of the camera the ray starts (every distance
// shifted). The first definition (s = ln t, clamped at t = 1e-3 in the scene's units) fails the
// second, as the last check shows: moving the camera changes every midpoint difference.
TEST(DistortionReference, LossIsTheSameInAnyUnitsAndFromAnyStart) {
  std::mt19937 rng(9);
  std::vector<float> sf, ff;
  randomRay(rng, 24, sf, ff);
  const std::vector<double> s(sf.begin(), sf.end());
  std::vector<double> w(24);
  std::uniform_real_distribution<double> u01(0, 1);
  double total = 0;
  for (double& x : w) total += x = u01(rng);
  for (double& x : w) x *= 0.95 / total;
  const double tNear = 0.8 * s[0], tFar = s[46] + s[47] + 3;
  auto scaled = [](std::vector<double> v, double k, double shift) {
    for (size_t i = 0; i < v.size(); i += 2) v[i] = v[i] * k + shift, v[i + 1] *= k;
    return v;
  };
  for (const ref::MarchSpacing<double>& m : {kConeSpacing, ref::MarchSpacing<double>{0, 0.05, 0.05}}) {
    const ref::DistortionRay<double> ray{m, tNear, tFar}, ray10{{m.coneAngle, 10 * m.dtMin, 10 * m.dtMax}, 10 * tNear, 10 * tFar};
    const auto s10 = scaled(s, 10, 0);
    const double loss = ref::distortionLoss<double>(s, w, ray);
    EXPECT_GT(loss, 1e-3);
    EXPECT_NEAR(ref::distortionLoss<double>(s10, w, ray10), loss, 1e-12 * loss);
    const auto g = ref::distortionWeightGradient<double>(s, w, ray), g10 = ref::distortionWeightGradient<double>(s10, w, ray10);
    for (size_t i = 0; i < g.size(); ++i) EXPECT_NEAR(g10[i], g[i], 1e-12 * std::fabs(g[i]) + 1e-15) << i;
  }
  const ref::DistortionRay<double> constant{{0, 0.05, 0.05}, tNear, tFar}, moved{{0, 0.05, 0.05}, tNear + 1.5, tFar + 1.5};
  const double loss = ref::distortionLoss<double>(s, w, constant);
  EXPECT_NEAR(ref::distortionLoss<double>(scaled(s, 1, 1.5), w, moved), loss, 1e-12 * loss);
  auto lnLoss = [&](const std::vector<double>& v) {
    double l = 0;
    for (size_t i = 0; i < w.size(); ++i)
      for (size_t j = 0; j < w.size(); ++j)
        l += w[i] * w[j] * std::fabs(std::log(v[2 * i] + v[2 * i + 1] / 2) - std::log(v[2 * j] + v[2 * j + 1] / 2));
    return l;
  };
  EXPECT_GT(std::fabs(lnLoss(scaled(s, 1, 1.5)) - lnLoss(s)), 0.1 * lnLoss(s));
}

// Reference gradients against central differences of L = dC . C + dO * opacity + dD * depth, in
// double. Each loss separately, then all together. Steps of 1e-6 relative give truncation error
// ~1e-12 and rounding ~1e-10 relative to the O(1) loss, far inside the 1e-7 tolerance.
TEST(CompositeReference, GradientsMatchFiniteDifferences) {
  std::mt19937 rng(7);
  std::vector<float> sf, ff;
  randomRay(rng, 12, sf, ff);
  std::vector<double> s(sf.begin(), sf.end()), f(ff.begin(), ff.end());
  f[4 * 5 + 3] = 0;          // a transparent sample
  s[2 * 7 + 1] = 0;          // a duplicate (zero-length) sample
  f[4 * 9 + 3] = 30;         // a nearly opaque one
  const std::array<double, 3> bg = {0.2, 0.5, 0.8};
  const std::array<std::array<double, 4>, 4> dCs = {{{0.9, -0.3, 0.4, 0}, {0, 0, 0, 0}, {0, 0, 0, 1.3}, {0.5, 0.2, -0.7, -0.6}}};
  const double dDs[4] = {0, 1.1, 0, -0.4};
  for (int c = 0; c < 4; ++c) {
    auto loss = [&](const std::vector<double>& field) {
      auto o = ref::compositeForward<double>(s, field, bg);
      return dCs[c][0] * o.rgb[0] + dCs[c][1] * o.rgb[1] + dCs[c][2] * o.rgb[2] + dCs[c][3] * o.opacity + dDs[c] * o.depth;
    };
    auto grad = ref::compositeBackward<double>(s, f, bg, dCs[c], dDs[c]);
    for (size_t i = 0; i < 12; ++i) {
      for (int k = 0; k < 4; ++k) {
        double h = 1e-6 * std::max(1.0, std::fabs(f[4 * i + k]));
        auto fp = f, fm = f;
        fp[4 * i + k] += h;
        fm[4 * i + k] -= h;
        // The formulas extend smoothly to sigma < 0, so sigma = 0 takes a centred difference too.
        double fd = (loss(fp) - loss(fm)) / (2 * h);
        EXPECT_NEAR(grad[i][k], fd, 1e-7 * std::max(1.0, std::fabs(fd))) << "case " << c << " sample " << i << " k " << k;
      }
    }
    EXPECT_EQ(grad[7][3], 0.0);  // delta = 0: sigma has no effect
  }
}

// The same with the distortion loss: L = dC . C + lambda * distortionLoss(w), alone (dC = 0) and
// with the colour term, over a ray whose first sample starts at t = 0 (its near), in cone steps;
// without and with the far field's interval (whose T_final = 1 - sum w moves with every sigma).
// Same steps and tolerance as above: the loss is O(1) and smooth in sigma.
TEST(CompositeReference, DistortionGradientsMatchFiniteDifferences) {
  std::mt19937 rng(8);
  std::vector<float> sf, ff;
  randomRay(rng, 12, sf, ff);
  std::vector<double> s(sf.begin(), sf.end()), f(ff.begin(), ff.end());
  for (size_t i = 0; i < 12; ++i) s[2 * i] -= sf[0];  // from t = 0
  f[4 * 5 + 3] = 0;   // a transparent sample
  s[2 * 7 + 1] = 0;   // a duplicate sample
  const std::array<double, 3> bg = {0.2, 0.5, 0.8};
  const std::array<std::array<double, 4>, 2> dCs = {{{0, 0, 0, 0}, {0.9, -0.3, 0.4, 0.2}}};
  // Sample 9 nearly opaque, or faint enough that the far field keeps a visible share of the ray.
  for (auto [farField, sigma9] : {std::pair{false, 30.0}, std::pair{true, 30.0}, std::pair{true, 0.3}}) {
    f[4 * 9 + 3] = sigma9;
    const ref::DistortionRay<double> ray{kConeSpacing, 0, s[22] + s[23] + 1, farField};
    for (double lambda : {1.0, 0.01}) {
      for (const auto& dc : dCs) {
        auto loss = [&](const std::vector<double>& field) {
          auto o = ref::compositeForward<double>(s, field, bg);
          return dc[0] * o.rgb[0] + dc[1] * o.rgb[1] + dc[2] * o.rgb[2] + dc[3] * o.opacity +
                 lambda * ref::distortionLoss<double>(s, o.weights, ray);
        };
        auto grad = ref::compositeBackward<double>(s, f, bg, dc, 0.0, lambda, ray);
        double largest = 0;
        for (size_t i = 0; i < 12; ++i) {
          double h = 1e-6 * std::max(1.0, std::fabs(f[4 * i + 3]));
          auto fp = f, fm = f;
          fp[4 * i + 3] += h;
          fm[4 * i + 3] -= h;
          double fd = (loss(fp) - loss(fm)) / (2 * h);
          EXPECT_NEAR(grad[i][3], fd, 1e-7 * std::max(1.0, std::fabs(fd)))
              << "lambda " << lambda << " far field " << farField << " sigma_9 " << sigma9 << " sample " << i;
          largest = std::max(largest, std::fabs(fd));
        }
        // Not a tolerance: the loss's part alone (dC = 0) must be a visible fraction of its weight.
        EXPECT_GT(largest, 1e-2 * lambda) << "the loss should depend on the densities";
        EXPECT_EQ(grad[7][3], 0.0);
      }
    }
  }
}

// sigma = 0 everywhere: C = bg exactly, opacity 0, depth 0, w = 0, dc = 0, and
// dL/dsigma_i = delta_i (dC . (c_i - bg) + dD t_i + dO) in closed form (T = 1, Q = bg).
TEST_F(Composite, HardZeroDensity) {
  std::mt19937 rng(3);
  std::vector<float> s, f;
  randomRay(rng, 16, s, f);
  for (size_t i = 0; i < 16; ++i) f[4 * i + 3] = 0;
  const std::array<float, 3> bg = {0.25f, 0.5f, 1.0f};
  const std::array<float, 4> dc = {0.7f, -0.4f, 0.25f, 0.5f};
  const float dd = -0.3f;
  auto b = singleRay(s, f, bg, dc, dd);
  std::vector<double> sd(s.begin(), s.end()), fd(f.begin(), f.end());
  auto ref = ref::compositeForward<double>(sd, fd, {bg[0], bg[1], bg[2]});
  auto grad = ref::compositeBackward<double>(sd, fd, {bg[0], bg[1], bg[2]}, {dc[0], dc[1], dc[2], dc[3]}, dd);
  auto g = runGpu(ctx(), b);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(g.color[k], bg[k]);
    EXPECT_EQ(ref.rgb[k], bg[k]);
  }
  EXPECT_EQ(g.color[3], 0.0f);
  EXPECT_EQ(ref.opacity, 0.0);
  EXPECT_EQ(g.depth[0], 0.0f);
  for (size_t i = 0; i < 16; ++i) {
    EXPECT_EQ(g.weights[i], 0.0f);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(g.dField[4 * i + k], 0.0f);
    double closed = double(s[2 * i + 1]) * (double(dc[3]) + double(dd) * s[2 * i]);
    for (int k = 0; k < 3; ++k) closed += double(s[2 * i + 1]) * dc[k] * (double(f[4 * i + k]) - bg[k]);
    EXPECT_NEAR(grad[i][3], closed, 1e-15);
    // A handful of float roundings of O(1) terms times delta.
    EXPECT_TRUE(test::near(g.dField[4 * i + 3], closed, 0, 1e-6 * s[2 * i + 1]));
  }
  EXPECT_TRUE(rayMatches(g, b, 0));
}

// One sample of huge, maximal or infinite density: its alpha is exactly 1, nothing behind it is
// seen (weights and every gradient there exactly 0), the background is hidden, opacity exactly 1.
TEST_F(Composite, HardOpaqueSample) {
  for (float huge : {1e30f, FLT_MAX, kInf}) {
    std::mt19937 rng(5);
    std::vector<float> s, f;
    randomRay(rng, 10, s, f);
    const size_t k = 4;
    f[4 * k + 3] = huge;
    f[4 * 7 + 3] = huge;  // a second wall behind the first changes nothing
    auto b = singleRay(s, f, {0.3f, 0.3f, 0.3f});
    auto g = runGpu(ctx(), b);
    std::vector<double> sd(s.begin(), s.end()), fd(f.begin(), f.end());
    auto ref = ref::compositeForward<double>(sd, fd, {0.3, 0.3, 0.3});
    auto grad = ref::compositeBackward<double>(sd, fd, {0.3, 0.3, 0.3}, {0.7, -0.4, 0.25, 0.5}, -0.3);
    SCOPED_TRACE(huge);
    ASSERT_TRUE(allFinite(g.color) && allFinite(g.depth) && allFinite(g.weights) && allFinite(g.dField));
    // The float reference meets the same input without inf arithmetic either.
    auto refF = ref::compositeForward<float>(s, f, {0.3f, 0.3f, 0.3f});
    auto gradF = ref::compositeBackward<float>(s, f, {0.3f, 0.3f, 0.3f}, {0.7f, -0.4f, 0.25f, 0.5f}, -0.3f);
    EXPECT_EQ(refF.opacity, 1.0f);
    EXPECT_TRUE(allFinite(refF.weights) && std::isfinite(refF.depth));
    for (size_t i = 0; i < 10; ++i) EXPECT_TRUE(std::isfinite(gradF[i][3]) && (i < k || gradF[i][3] == 0.0f));
    EXPECT_EQ(g.color[3], 1.0f);
    EXPECT_EQ(ref.opacity, 1.0);
    double tK = 0;  // the wall takes all the light that reaches it
    for (size_t i = 0; i < k; ++i) tK += ref.weights[i];
    EXPECT_NEAR(ref.weights[k], 1 - tK, 1e-15);
    for (size_t i = k + 1; i < 10; ++i) {
      EXPECT_EQ(g.weights[i], 0.0f);
      EXPECT_EQ(ref.weights[i], 0.0);
      for (int c = 0; c < 4; ++c) {
        EXPECT_EQ(g.dField[4 * i + c], 0.0f) << "sample " << i;
        EXPECT_EQ(grad[i][c], 0.0);
      }
    }
    EXPECT_EQ(g.dField[4 * k + 3], 0.0f);  // saturated: T after it and T_final are both 0
    EXPECT_EQ(grad[k][3], 0.0);
    EXPECT_GT(g.dField[4 * k], 0.0f);  // its colour still counts
    EXPECT_TRUE(rayMatches(g, b, 0));
  }
}

// sigma * delta = 1e-8: alpha must be ~1e-8 to 1e-4 relative, not 1 - exp(-1e-8) = 0 in float.
TEST_F(Composite, HardTinyOpticalDepth) {
  std::vector<float> s, f;
  for (int i = 0; i < 4; ++i) {
    s.insert(s.end(), {1.0f + 0.1f * i, 0.1f});
    f.insert(f.end(), {0.2f * i, 1.0f, 0.5f, 1e-7f});
  }
  auto b = singleRay(s, f, {0, 0, 0}, {1, 0.5f, 0.25f, 1}, 1);
  auto g = runGpu(ctx(), b);
  std::vector<double> sd(s.begin(), s.end()), fd(f.begin(), f.end());
  auto ref = ref::compositeForward<double>(sd, fd, {0, 0, 0});
  auto grad = ref::compositeBackward<double>(sd, fd, {0, 0, 0}, {1, 0.5, 0.25, 1}, 1);
  for (int i = 0; i < 4; ++i) {
    double x = double(f[4 * i + 3]) * double(s[2 * i + 1]);
    EXPECT_NEAR(ref.weights[i] / x, 1.0, 1e-7);  // T ~ 1 and alpha ~ x
    EXPECT_TRUE(test::near(g.weights[i], ref.weights[i], 1e-4, 0));
    EXPECT_TRUE(test::near(g.dField[4 * i], grad[i][0], 1e-4, 0));
    EXPECT_TRUE(test::near(g.dField[4 * i + 3], grad[i][3], 1e-4, 0));
  }
  EXPECT_TRUE(test::near(g.color[3], ref.opacity, 1e-4, 0));
  EXPECT_TRUE(test::near(g.color[1], ref.rgb[1], 1e-4, 0));
  EXPECT_TRUE(test::near(g.depth[0], ref.depth, 1e-4, 0));
  EXPECT_GT(g.color[3], 3.9e-8f);
  EXPECT_TRUE(rayMatches(g, b, 0));
}

// Duplicate samples (delta = 0), even with sigma = inf, change nothing: the ray composites exactly
// as it does without them, and their weights and gradients are exactly 0.
TEST_F(Composite, HardZeroDelta) {
  std::mt19937 rng(9);
  std::vector<float> s, f;
  randomRay(rng, 8, s, f);
  std::vector<float> s2, f2;
  std::vector<bool> dup;
  for (size_t i = 0; i < 8; ++i) {
    s2.insert(s2.end(), {s[2 * i], s[2 * i + 1]});
    f2.insert(f2.end(), {f[4 * i], f[4 * i + 1], f[4 * i + 2], f[4 * i + 3]});
    dup.push_back(false);
    if (i % 3 == 0) {  // a duplicate of sample i's position with a wild density
      s2.insert(s2.end(), {s[2 * i], 0.0f});
      f2.insert(f2.end(), {0.9f, 0.1f, 0.5f, i == 0 ? kInf : (i == 3 ? FLT_MAX : 1e30f)});
      dup.push_back(true);
    }
  }
  Batch b;
  b.addRay(s, f, {0.1f, 0.2f, 0.3f}, {0.7f, -0.4f, 0.25f, 0.5f}, -0.3f);
  b.addRay(s2, f2, {0.1f, 0.2f, 0.3f}, {0.7f, -0.4f, 0.25f, 0.5f}, -0.3f);
  auto g = runGpu(ctx(), b);
  ASSERT_TRUE(allFinite(g.dField) && allFinite(g.weights));
  for (int c = 0; c < 4; ++c) EXPECT_EQ(g.color[4 + c], g.color[c]);
  EXPECT_EQ(g.depth[1], g.depth[0]);
  for (size_t j = 0, i = 0; j < dup.size(); ++j) {
    const size_t at = 8 + j;
    if (dup[j]) {
      EXPECT_EQ(g.weights[at], 0.0f);
      for (int c = 0; c < 4; ++c) EXPECT_EQ(g.dField[4 * at + c], 0.0f);
    } else {
      EXPECT_EQ(g.weights[at], g.weights[i]);
      for (int c = 0; c < 4; ++c) EXPECT_EQ(g.dField[4 * at + c], g.dField[4 * i + c]);
      ++i;
    }
  }
  auto grad = ref::compositeBackward<double>(b.raySamples(1), b.rayField(1), {0.1, 0.2, 0.3}, {0.7, -0.4, 0.25, 0.5}, -0.3);
  for (size_t j = 0; j < dup.size(); ++j)
    if (dup[j]) EXPECT_EQ(grad[j][3], 0.0);
  EXPECT_TRUE(rayMatches(g, b, 0));
  EXPECT_TRUE(rayMatches(g, b, 1));
}

// The last sample's segment is open (delta = 1e10, as vanilla NeRF pads it): dense, it swallows
// the background exactly; transparent, the background shows; faint, its huge but finite gradient
// matches the reference.
TEST_F(Composite, HardOpenLastSegment) {
  std::mt19937 rng(13);
  std::vector<float> s, f;
  randomRay(rng, 6, s, f);
  for (size_t i = 0; i < 6; ++i) f[4 * i + 3] *= 0.05f;  // let light reach the end
  s[2 * 5 + 1] = 1e10f;
  Batch b;
  for (float last : {2.0f, 0.0f, 1e-12f}) {
    f[4 * 5 + 3] = last;
    b.addRay(s, f, {0.5f, 0.5f, 0.5f}, {0.7f, -0.4f, 0.25f, 0.5f}, -0.3f);
  }
  auto g = runGpu(ctx(), b);
  ASSERT_TRUE(allFinite(g.color) && allFinite(g.depth) && allFinite(g.weights) && allFinite(g.dField));
  EXPECT_EQ(g.color[3], 1.0f);           // dense: opaque
  EXPECT_EQ(g.dField[4 * 5 + 3], 0.0f);  // and saturated
  EXPECT_LT(g.color[4 + 3], 1.0f);       // transparent: background seen
  EXPECT_GT(std::fabs(g.dField[4 * 11 + 3]), 1e6f);
  EXPECT_GT(g.color[8 + 3], g.color[4 + 3]);  // faint: x = 0.01 adds a little
  for (uint32_t r = 0; r < 3; ++r) EXPECT_TRUE(rayMatches(g, b, r));
}

// Rays with no samples (packed layout) and missed rays (fixed layout, all deltas 0) show the
// background and get no gradient; an empty batch records nothing.
TEST_F(Composite, HardEmptyAndMissedRays) {
  std::mt19937 rng(17);
  std::vector<float> s, f;
  Batch packed;
  for (uint32_t r = 0; r < 6; ++r) {
    randomRay(rng, r % 2 ? 5 : 0, s, f);
    packed.addRay(s, f, {0.1f * r, 0.5f, 1.0f - 0.1f * r}, randomDColor(rng), 0.5f);
  }
  auto g = runGpu(ctx(), packed);
  for (uint32_t r = 0; r < 6; r += 2) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(g.color[4 * r + k], packed.perRayBg[4 * r + k]);
    EXPECT_EQ(g.color[4 * r + 3], 0.0f);
    EXPECT_EQ(g.depth[r], 0.0f);
  }
  for (uint32_t r = 0; r < 6; ++r) EXPECT_TRUE(rayMatches(g, packed, r));

  Batch fixed;
  fixed.samplesPerRay = 4;
  randomRay(rng, 4, s, f);
  fixed.addRay(s, f, {0.2f, 0.2f, 0.2f}, randomDColor(rng), 1);
  std::vector<float> missS = {-1, 0, -1, 0, -1, 0, -1, 0};  // a missed ray: t = -1, no length
  std::vector<float> missF = {1, 1, 1, 5, 1, 1, 1, kInf, 0, 0, 0, 0, 1, 0, 0, 1e30f};
  fixed.addRay(missS, missF, {0.9f, 0.8f, 0.7f}, randomDColor(rng), 1);
  auto h = runGpu(ctx(), fixed);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(h.color[4 + k], fixed.perRayBg[4 + k]);
  EXPECT_EQ(h.color[7], 0.0f);
  EXPECT_EQ(h.depth[1], 0.0f);
  for (int i = 4; i < 8; ++i) {
    EXPECT_EQ(h.weights[i], 0.0f);
    for (int c = 0; c < 4; ++c) EXPECT_EQ(h.dField[4 * i + c], 0.0f);
  }
  for (uint32_t r = 0; r < 2; ++r) EXPECT_TRUE(rayMatches(h, fixed, r));

  Batch none;
  auto z = runGpu(ctx(), none);
  EXPECT_TRUE(z.color.empty());
}

// 4096 samples on one ray: S_total ~ 215, so T underflows to 0 about halfway along. Gradients stay
// finite, match the double reference where little light still arrives (where "total minus prefix"
// suffix sums drift out of the error bound) and are exactly 0 where none does.
TEST_F(Composite, HardLongRayUnderflow) {
  std::mt19937 rng(19);
  std::vector<float> s, f;
  randomRay(rng, 4096, s, f);
  for (size_t i = 0; i < 4096; ++i) f[4 * i + 3] = 0.5f + float(rng() % 1000) / 1000.0f;
  auto b = singleRay(s, f, {0.4f, 0.4f, 0.4f});
  b.samplesPerRay = 4096;
  auto g = runGpu(ctx(), b);
  ASSERT_TRUE(allFinite(g.color) && allFinite(g.depth) && allFinite(g.weights) && allFinite(g.dField));
  auto grad = ref::compositeBackward<double>(b.raySamples(0), b.rayField(0), {0.4, 0.4, 0.4}, {0.7, -0.4, 0.25, 0.5}, -0.3);
  size_t zeros = 0;
  for (size_t i = 0; i < 4096; ++i) {
    // Below 1e-50, T < 1e-49 in double: exp of that exponent is 0 in float, denormals or not.
    if (std::fabs(grad[i][3]) < 1e-50) {
      EXPECT_EQ(g.dField[4 * i + 3], 0.0f) << "sample " << i;
      ++zeros;
    }
  }
  EXPECT_GT(zeros, 1000u);  // the underflow region is really exercised
  EXPECT_TRUE(rayMatches(g, b, 0));
}

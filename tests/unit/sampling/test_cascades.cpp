// Occupancy cascades for unbounded scenes: the update points of every cascade, the cascaded cone
// march (shaders/occupancy/occupancy.glsl) against ref::marchRayCascaded bit for bit, the step-size
// rule, and which cascade and cell a world point lands in, checked against plain geometry.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/occupancy/occupancy_grid.h"
#include "nerf/sampling/ray_marcher.h"
#include "reference/occupancy/occupancy_grid.h"
#include "reference/rays/rays.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

class Cascades : public test::GpuTest {};

struct TestRay {
  std::array<float, 3> o, d;
  float tNear = -1, tFar = -1;
};

// Origins anywhere in a cube 1.2 times the box (inside the inner cube too, as a camera standing in
// the scene), aimed at random points of the box; clipped to the box with a near plane of 0.05.
std::vector<TestRay> randomRays(uint32_t n, const Aabb& box, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
  std::vector<TestRay> out;
  for (uint32_t i = 0; i < n; ++i) {
    std::array<float, 3> o, d;
    float norm = 0;
    const float reach = i % 2 ? 0.15f : 1.2f;  // half the origins near the centre
    for (int k = 0; k < 3; ++k) {
      const float c = 0.5f * (box.min[k] + box.max[k]), h = 0.5f * (box.max[k] - box.min[k]);
      o[k] = c + reach * h * uni(rng);
      d[k] = c + h * uni(rng) - o[k];
      norm += d[k] * d[k];
    }
    for (auto& v : d) v /= std::sqrt(norm);
    ref::Ray<float> r{o, d};
    ref::intersectAabb(r, box, 0.05f);
    out.push_back({o, d, r.tNear, r.tFar});
  }
  return out;
}

struct MarchOut {
  std::vector<uint32_t> offsets;
  std::vector<float> samples;  // (t, delta) per sample
};

MarchOut runMarch(Context& ctx, const std::vector<TestRay>& rays, const nerf::OccupancyGrid& grid, const Aabb& box,
                  float dt, const nerf::ConeSteps& cone, uint32_t maxSamples, uint32_t seed, bool jitter) {
  const uint32_t n = uint32_t(rays.size());
  std::vector<float> packed;
  for (const auto& r : rays) packed.insert(packed.end(), {r.o[0], r.o[1], r.o[2], r.tNear, r.d[0], r.d[1], r.d[2], r.tFar});
  auto rayBuf = gpu::Buffer::of(ctx, packed);
  const uint64_t capacity = uint64_t(n) * maxSamples;
  gpu::Buffer offsets(ctx, (n + 1) * 4), samples(ctx, capacity * 8), sampleRay(ctx, capacity * 4), totals(ctx, 16);
  nerf::RayMarcher marcher(ctx, n);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    marcher.record(rec, {rayBuf, n}, grid, box, {dt, maxSamples, seed, jitter, cone},
                   {offsets, samples, sampleRay, totals});
  });
  MarchOut out{offsets.download<uint32_t>(n + 1), {}};
  out.samples = samples.download<float>(size_t(out.offsets[n]) * 2);
  return out;
}

// The reference's parameters for a march of `cascades` grids of resolution^3 over `box`.
ref::ConeMarchParams paramsFor(uint32_t resolution, uint32_t cascades, const Aabb& box, float dt,
                               const nerf::ConeSteps& cone, uint32_t maxSamples, uint32_t seed, bool jitter) {
  const Aabb inner = nerf::RayMarcher::innerCube(box, cascades);
  ref::ConeMarchParams p;
  p.base.boxMin = inner.min;
  p.base.gridScale = ref::gridScale(resolution, inner.min, inner.max);
  p.base.resolution = resolution;
  p.base.dt = dt;
  p.base.maxSamples = maxSamples;
  p.base.seed = seed;
  p.base.jitter = jitter;
  p.cascades = cascades;
  p.coneAngle = cone.coneAngle;
  p.dtMax = cone.dtMax;
  p.stepOpacity = cone.stepOpacity;
  p.stretch = cone.stretch;
  return p;
}

ref::ConeMarchParams paramsFor(const nerf::OccupancyGrid& grid, const Aabb& box, float dt, const nerf::ConeSteps& cone,
                               uint32_t maxSamples, uint32_t seed, bool jitter) {
  return paramsFor(grid.resolution(), grid.cascades(), box, dt, cone, maxSamples, seed, jitter);
}

std::vector<uint32_t> randomBits(const nerf::OccupancyGrid& grid, double p, uint32_t seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution on(p);
  std::vector<uint32_t> bits(grid.numWords());
  for (uint32_t i = 0; i < grid.numCells(); ++i)
    if (on(rng)) ref::setBit(bits, i);
  return bits;
}

// An anisotropic box with 3 cascades of 8^3: the inner cube is a quarter of the box.
const Aabb kBox{{-4.0f, -2.0f, -3.0f}, {4.0f, 2.0f, 5.0f}};
constexpr uint32_t kRes = 8, kCascades = 3;

float diagonal(const Aabb& b) {
  return std::hypot(b.max[0] - b.min[0], b.max[1] - b.min[1], b.max[2] - b.min[2]);
}

}  // namespace

TEST_F(Cascades, UpdatePointsLieInTheCellsOfTheirCascade) {
  const uint32_t seed = 31;
  nerf::OccupancyGrid grid(ctx(), kRes, kCascades);
  ASSERT_EQ(grid.numCells(), kRes * kRes * kRes * kCascades);
  gpu::Buffer pos(ctx(), VkDeviceSize(grid.numCells()) * 16), cells(ctx(), VkDeviceSize(grid.numCells()) * 4);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) { grid.recordAllCellPoints(rec, seed, pos, cells); });
  const auto p = pos.download<float>(size_t(grid.numCells()) * 4);
  const auto c = cells.download<uint32_t>(grid.numCells());
  const uint32_t perCascade = kRes * kRes * kRes;
  for (uint32_t j = 0; j < grid.numCells(); ++j) {
    ASSERT_EQ(c[j], j);
    const auto expected = ref::cellPointPosition<double>(j, kRes, seed, j, kCascades);
    // Cascade k spans 2^(k - 2) of the normalised box: cells of side 2^(k - 2) * 2 / R.
    const uint32_t cascade = j / perCascade, local = j % perCascade;
    const double scale = std::ldexp(1.0, int(cascade) - int(kCascades - 1));
    const uint32_t cell[3] = {local % kRes, (local / kRes) % kRes, local / (kRes * kRes)};
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(test::near(p[4 * j + k], expected[k], 0, 4e-7));
      const double lo = (-1.0 + 2.0 * cell[k] / kRes) * scale, hi = (-1.0 + 2.0 * (cell[k] + 1) / kRes) * scale;
      EXPECT_GE(p[4 * j + k], lo - 1e-6);
      EXPECT_LE(p[4 * j + k], hi + 1e-6);
    }
  }
}

TEST_F(Cascades, RandomUpdateCellsCoverEveryCascade) {
  const uint32_t seed = 8, count = 4000;
  nerf::OccupancyGrid grid(ctx(), kRes, kCascades);
  gpu::Buffer pos(ctx(), VkDeviceSize(count) * 16), cells(ctx(), VkDeviceSize(count) * 4);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) { grid.recordRandomCellPoints(rec, seed, count, pos, cells); });
  const auto c = cells.download<uint32_t>(count);
  std::vector<uint32_t> perCascade(kCascades, 0);
  for (uint32_t j = 0; j < count; ++j) {
    ASSERT_EQ(c[j], ref::cellPointCell(kRes, seed, j, true, kCascades));
    ++perCascade[c[j] / (kRes * kRes * kRes)];
  }
  for (uint32_t n : perCascade) EXPECT_GT(n, count / kCascades / 2);
}

TEST_F(Cascades, ConeMarchMatchesReference) {
  nerf::OccupancyGrid grid(ctx(), kRes, kCascades);
  const float dt = diagonal(nerf::RayMarcher::innerCube(kBox, kCascades)) / 64.0f;
  const nerf::ConeSteps cone{1.0f / 32.0f, diagonal(kBox) / kRes};  // steep, so steps grow inside the box
  const auto rays = randomRays(2000, kBox, 12);
  uint64_t total = 0;
  for (double p : {0.15, 0.7}) {
    const auto bits = randomBits(grid, p, uint32_t(p * 100));
    grid.bits().upload(bits);
    for (bool jitter : {false, true})
      for (uint32_t maxSamples : {4096u, 7u}) {
        const auto out = runMarch(ctx(), rays, grid, kBox, dt, cone, maxSamples, 5, jitter);
        const auto params = paramsFor(grid, kBox, dt, cone, maxSamples, 5, jitter);
        for (uint32_t r = 0; r < rays.size(); ++r) {
          const auto& ray = rays[r];
          const auto expected = ref::marchRayCascaded<float>(ray.o, ray.d, ray.tNear, ray.tFar, r, params, bits);
          const uint32_t first = out.offsets[r], count = out.offsets[r + 1] - first;
          ASSERT_EQ(count, expected.size()) << "ray " << r;
          for (uint32_t i = 0; i < count; ++i) {
            EXPECT_EQ(out.samples[2 * (first + i)], expected[i].t) << "ray " << r << " sample " << i;
            EXPECT_EQ(out.samples[2 * (first + i) + 1], expected[i].delta) << "ray " << r << " sample " << i;
          }
          total += count;
        }
      }
  }
  EXPECT_GT(total, 50000u);  // the comparison saw real work
}

// Densities log-uniform so that one step dt is from 1e-3 to 1 optically thick: the stretch meets
// cells that allow many steps, a few, and none.
std::vector<float> randomDensities(uint32_t cells, float dt, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> exponent(-3.0f, 0.0f);
  std::vector<float> density(cells);
  for (auto& d : density) d = std::pow(10.0f, exponent(rng)) / dt;
  return density;
}

TEST_F(Cascades, StretchedConeMarchMatchesReference) {
  // A bound of 0.05, and the largest float: the proposal's candidates, stretched through every
  // occupied cell without a density read.
  nerf::OccupancyGrid grid(ctx(), kRes, kCascades);
  const float dt = diagonal(nerf::RayMarcher::innerCube(kBox, kCascades)) / 64.0f;
  const auto rays = randomRays(2000, kBox, 13);
  const auto bits = randomBits(grid, 0.7, 70);
  const auto density = randomDensities(grid.numCells(), dt, 3);
  grid.bits().upload(bits);
  grid.density().upload(density);
  uint64_t samplesAt[2] = {0, 0};
  for (int bound = 0; bound < 2; ++bound) {
    const float opacity = bound == 0 ? 0.05f : std::numeric_limits<float>::max();
    const nerf::ConeSteps cone{1.0f / 32.0f, diagonal(kBox) / kRes, opacity, 16};
    uint64_t total = 0, stretched = 0;
    for (bool jitter : {false, true}) {
      const auto out = runMarch(ctx(), rays, grid, kBox, dt, cone, 4096, 5, jitter);
      const auto params = paramsFor(grid, kBox, dt, cone, 4096, 5, jitter);
      for (uint32_t r = 0; r < rays.size(); ++r) {
        const auto& ray = rays[r];
        const auto expected = ref::marchRayCascaded<float>(ray.o, ray.d, ray.tNear, ray.tFar, r, params, bits, density);
        const uint32_t first = out.offsets[r], count = out.offsets[r + 1] - first;
        ASSERT_EQ(count, expected.size()) << "ray " << r << " bound " << opacity;
        for (uint32_t i = 0; i < count; ++i) {
          EXPECT_EQ(out.samples[2 * (first + i)], expected[i].t) << "ray " << r << " sample " << i << " bound " << opacity;
          EXPECT_EQ(out.samples[2 * (first + i) + 1], expected[i].delta) << "ray " << r << " sample " << i << " bound " << opacity;
          stretched += i + 1 < count && expected[i].delta > 1.5f * ref::coneStep(expected[i].t, params);
        }
        total += count;
      }
    }
    EXPECT_GT(total, bound == 0 ? 20000u : 5000u) << "bound " << opacity;  // the comparison saw real work
    EXPECT_GT(stretched, total / 20) << "bound " << opacity;                // and stretched samples among it
    samplesAt[bound] = total;
  }
  // Unbounded, no density stops a stretch: the same rays take fewer, longer samples.
  EXPECT_LT(samplesAt[1], samplesAt[0]);
}

TEST(CascadeReference, AStretchedSampleStaysUnderItsOpacityBound) {
  // Checked from plain geometry in double: a sample that stands for n steps has the points
  // t + k dt (k < n) of those steps in occupied cells, and the largest density among those cells
  // times its delta is at most the bound.
  const uint32_t cells = kRes * kRes * kRes * kCascades;
  std::mt19937 rng(21);
  std::bernoulli_distribution on(0.8);
  std::vector<uint32_t> bits((cells + 31) / 32);
  for (uint32_t i = 0; i < cells; ++i)
    if (on(rng)) ref::setBit(bits, i);
  const Aabb inner = nerf::RayMarcher::innerCube(kBox, kCascades);
  const float dt = diagonal(inner) / 64.0f, bound = 0.08f;
  const auto density = randomDensities(cells, dt, 22);
  const auto p = paramsFor(kRes, kCascades, kBox, dt, {1.0f / 32.0f, diagonal(kBox) / kRes, bound, 16}, 100000, 0, false);
  // The cell of a world point, from the geometry: the smallest cube about the centre holding it;
  // `ambiguous` where the point lies within float rounding of a cell face or a cascade's border.
  const auto cellOf = [&](const std::array<double, 3>& x, bool& ambiguous) {
    double q[3], m = 0;
    for (int k = 0; k < 3; ++k) {
      const double centre = 0.5 * (kBox.min[k] + kBox.max[k]), half = 0.5 * (inner.max[k] - inner.min[k]);
      q[k] = (x[k] - centre) / half;
      m = std::max(m, std::fabs(q[k]));
    }
    const uint32_t c = m <= 1 ? 0 : m <= 2 ? 1 : 2;
    ambiguous = std::fabs(m - 1) < 1e-4 || std::fabs(m - 2) < 1e-4;
    uint32_t g[3];
    for (int k = 0; k < 3; ++k) {
      const double u = (q[k] / std::ldexp(1.0, int(c)) + 1) * 0.5 * kRes;
      ambiguous = ambiguous || std::fabs(u - std::round(u)) < 1e-3;
      g[k] = uint32_t(std::clamp(std::floor(u), 0.0, double(kRes - 1)));
    }
    return c * kRes * kRes * kRes + ref::cellIndex(g[0], g[1], g[2], kRes);
  };
  uint32_t stretched = 0, checked = 0;
  for (const auto& ray : randomRays(500, kBox, 6)) {
    for (const auto& s : ref::marchRayCascaded<float>(ray.o, ray.d, ray.tNear, ray.tFar, 0, p, bits, density)) {
      const double step = ref::coneStep<float>(s.t, p);
      const uint32_t n = uint32_t(std::lround(s.delta / step));
      if (n <= 1) continue;
      ++stretched;
      double sigma = 0;
      for (uint32_t k = 0; k < n; ++k) {
        const double tk = s.t + k * step;
        std::array<double, 3> x;
        for (int a = 0; a < 3; ++a) x[a] = ray.o[a] + tk * ray.d[a];
        bool ambiguous;
        const uint32_t cell = cellOf(x, ambiguous);
        if (ambiguous) continue;
        EXPECT_TRUE(ref::bitSet(bits, cell)) << "t " << s.t << " step " << k << " of " << n;
        sigma = std::max(sigma, double(density[cell]));
      }
      EXPECT_LE(sigma * s.delta, bound * (1 + 1e-5)) << "t " << s.t << " n " << n;
      ++checked;
    }
  }
  EXPECT_GT(stretched, 500u);
  EXPECT_EQ(checked, stretched);
}

TEST(CascadeReference, AUniformFogIsCrossedInEqualStretchedSteps) {
  // Every cell occupied, each step a quarter of the bound thick (a hair under, so that rounding
  // cannot tip it): inside the box every sample but the last stands for exactly 4 steps.
  const uint32_t cells = kRes * kRes * kRes * kCascades;
  const std::vector<uint32_t> bits((cells + 31) / 32, ~0u);
  const float dt = 0.01f, bound = 0.05f;
  const std::vector<float> density(cells, bound / (4 * dt) * 0.999f);
  const auto p = paramsFor(kRes, kCascades, kBox, dt, {0, dt, bound, 16}, 100000, 0, false);  // a constant step
  uint32_t rays = 0;
  for (const auto& ray : randomRays(100, kBox, 2)) {
    const auto s = ref::marchRayCascaded<float>(ray.o, ray.d, ray.tNear, ray.tFar, 0, p, bits, density);
    if (s.size() < 2) continue;
    ++rays;
    for (size_t i = 0; i + 1 < s.size(); ++i) {
      EXPECT_FLOAT_EQ(s[i].delta, 4 * dt) << i;
      // a difference of two t of ~1 to 10: their float rounding, a few 1e-7, is all it may differ by
      EXPECT_TRUE(test::near(s[i + 1].t - s[i].t, 4.0 * dt, 0, 2e-6)) << i;
    }
    EXPECT_LE(s.back().delta, 4 * dt);
  }
  EXPECT_GT(rays, 50u);
}

TEST_F(Cascades, StepsFollowTheConeRule) {
  // With every cell occupied nothing is skipped: consecutive samples are exactly one step apart,
  // and each step is clamp(t * angle, dtMin, dtMax) (computed here in double), or the rest to t_far.
  nerf::OccupancyGrid grid(ctx(), kRes, kCascades);
  const std::vector<uint32_t> bits(grid.numWords(), ~0u);
  const float dtMin = 0.01f, dtMax = 0.2f, angle = 1.0f / 16.0f;
  const auto params = paramsFor(grid, kBox, dtMin, {angle, dtMax}, 100000, 0, false);
  uint32_t grown = 0, capped = 0;
  for (const auto& ray : randomRays(300, kBox, 4)) {
    const auto s = ref::marchRayCascaded<float>(ray.o, ray.d, ray.tNear, ray.tFar, 0, params, bits);
    if (ray.tNear < 0) {
      EXPECT_TRUE(s.empty());
      continue;
    }
    ASSERT_FALSE(s.empty());
    EXPECT_EQ(s[0].t, ray.tNear);
    for (size_t i = 0; i < s.size(); ++i) {
      const double step = std::clamp(double(s[i].t) * angle, double(dtMin), double(dtMax));
      if (i + 1 < s.size()) {
        EXPECT_TRUE(test::near(s[i].delta, step, 1e-6, 0)) << i;
        EXPECT_TRUE(test::near(s[i + 1].t - s[i].t, step, 1e-5, 1e-6)) << i;
      } else {
        EXPECT_TRUE(test::near(s[i].delta, std::min(step, double(ray.tFar) - s[i].t), 1e-6, 1e-6));
        EXPECT_GE(s[i].t + step, ray.tFar * (1 - 1e-6));  // the next step would leave the box
      }
      grown += step > dtMin && step < dtMax;
      capped += step == dtMax;
    }
  }
  EXPECT_GT(grown, 1000u);
  EXPECT_GT(capped, 100u);
}

TEST_F(Cascades, SamplesLandOnlyInTheOccupiedCellOfEachCascade) {
  // One occupied cell per cascade. Which cascade a world point belongs to, and its cell there, are
  // computed here from the geometry alone (the smallest cube about the centre holding the point,
  // its side over R): every sample must lie in one of the three cells, and each of them is hit.
  nerf::OccupancyGrid grid(ctx(), kRes, kCascades);
  const uint32_t perCascade = kRes * kRes * kRes;
  const uint32_t chosen[kCascades][3] = {{3, 4, 4}, {1, 6, 2}, {7, 0, 5}};  // the outer two avoid the inner cubes
  std::vector<uint32_t> bits(grid.numWords());
  for (uint32_t c = 0; c < kCascades; ++c)
    ref::setBit(bits, c * perCascade + ref::cellIndex(chosen[c][0], chosen[c][1], chosen[c][2], kRes));
  grid.bits().upload(bits);
  // Rays from the centre to each chosen cell's centre and beyond, and random rays.
  std::vector<TestRay> rays = randomRays(3000, kBox, 9);
  for (uint32_t c = 0; c < kCascades; ++c) {
    std::array<float, 3> o{}, d{};
    float norm = 0;
    for (int k = 0; k < 3; ++k) {
      const double centre = 0.5 * (kBox.min[k] + kBox.max[k]), side = (kBox.max[k] - kBox.min[k]) * std::ldexp(1.0, int(c) - 2);
      o[k] = float(centre) + 0.01f;
      d[k] = float(centre - 0.5 * side + (chosen[c][k] + 0.5) * side / kRes) - o[k];
      norm += d[k] * d[k];
    }
    for (auto& v : d) v /= std::sqrt(norm);
    ref::Ray<float> r{o, d};
    ref::intersectAabb(r, kBox, 0.0f);
    rays.push_back({o, d, r.tNear, r.tFar});
  }
  const float dt = 0.02f;
  const nerf::ConeSteps cone{1.0f / 256.0f, 0.1f};
  const auto out = runMarch(ctx(), rays, grid, kBox, dt, cone, 4096, 0, false);
  uint32_t hits[kCascades] = {0, 0, 0};
  for (uint32_t r = 0; r < rays.size(); ++r)
    for (uint32_t i = out.offsets[r]; i < out.offsets[r + 1]; ++i) {
      const double t = out.samples[2 * i];
      double q[3], m = 0;
      for (int k = 0; k < 3; ++k) {
        const double centre = 0.5 * (kBox.min[k] + kBox.max[k]), half = 0.5 * (kBox.max[k] - kBox.min[k]) / 4;
        q[k] = (rays[r].o[k] + t * rays[r].d[k] - centre) / half;  // the inner cube is [-1, 1]^3
        m = std::max(m, std::fabs(q[k]));
      }
      const uint32_t c = m <= 1 ? 0 : m <= 2 ? 1 : 2;
      bool inChosen = true;
      for (int k = 0; k < 3; ++k) {
        const double g = (q[k] / std::ldexp(1.0, int(c)) + 1) * 0.5 * kRes;  // cell coordinate in cascade c
        // a sample within float rounding of a cell face may go either way
        inChosen = inChosen && g > chosen[c][k] - 1e-4 && g < chosen[c][k] + 1 + 1e-4;
      }
      EXPECT_TRUE(inChosen) << "ray " << r << " t " << t << " cascade " << c;
      ++hits[c];
    }
  for (uint32_t c = 0; c < kCascades; ++c) EXPECT_GT(hits[c], 0u) << "cascade " << c;
}

TEST(CascadeReference, PointsBelongToTheSmallestCascadeHoldingThem) {
  // Grid coordinates of cascade 0 with R = 8: the inner cube is [0, 8]^3, cascade c reaches 4 + 4 * 2^c.
  const auto cascade = [](float x) { return ref::cascadeOf<float>({x, 4.0f, 4.0f}, 8, 3); };
  EXPECT_EQ(cascade(4.0f), 0u);
  EXPECT_EQ(cascade(8.0f), 0u);  // on the inner cube's face
  EXPECT_EQ(cascade(8.001f), 1u);
  EXPECT_EQ(cascade(-4.0f), 1u);
  EXPECT_EQ(cascade(-4.001f), 2u);
  EXPECT_EQ(cascade(1e6f), 2u);  // beyond the outermost: the outermost
  const auto cell = ref::cascadeCell<float>({8.0f, -4.0f, 20.0f}, 8, 2);  // (g - 4) / 4 + 4
  EXPECT_EQ(cell[0], 5u);
  EXPECT_EQ(cell[1], 2u);
  EXPECT_EQ(cell[2], 7u);  // clamped into the grid
}

TEST_F(Cascades, BadConeStepsAreErrors) {
  nerf::OccupancyGrid grid(ctx(), kRes, kCascades);
  const auto rays = randomRays(4, kBox, 1);
  EXPECT_THROW(runMarch(ctx(), rays, grid, kBox, 0.1f, {1.0f / 256, 0.05f}, 16, 0, false), Error);  // dtMax < dt
  EXPECT_THROW(runMarch(ctx(), rays, grid, kBox, 0.1f, {-1.0f, 1.0f}, 16, 0, false), Error);
  EXPECT_THROW(runMarch(ctx(), rays, grid, kBox, 0.1f, {0.0f, 1.0f, -0.1f, 4}, 16, 0, false), Error);
  EXPECT_THROW(runMarch(ctx(), rays, grid, kBox, 0.1f, {0.0f, 1.0f, NAN, 4}, 16, 0, false), Error);
  EXPECT_THROW(runMarch(ctx(), rays, grid, kBox, 0.1f, {0.0f, 1.0f, 0.05f, 0}, 16, 0, false), Error);
  EXPECT_THROW(runMarch(ctx(), rays, grid, kBox, 0.1f, {0.0f, 1.0f, 0.05f, nerf::RayMarcher::kMaxStretch + 1}, 16, 0, false),
               Error);
  EXPECT_THROW(nerf::OccupancyGrid(ctx(), 8, 0), Error);
  EXPECT_THROW(nerf::OccupancyGrid(ctx(), 8, 9), Error);
  EXPECT_THROW(nerf::OccupancyGrid(ctx(), 256, 2), Error);  // 2^25 cells
}

// Packed ray marching with empty-space skipping (shaders/sampling/march_*.comp) and the prefix sum
// (shaders/gpu/scan_*.comp) against the CPU reference (tests/reference/occupancy/occupancy_grid.h), whose march visits
// every lattice point one at a time: identical sample sets show that skipping loses nothing.
// No gradients flow through sample positions, so there is no finite-difference check here.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/prefix_sum.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "nerf/occupancy/occupancy_grid.h"
#include "nerf/sampling/packed_points.h"
#include "nerf/sampling/ray_marcher.h"
#include "reference/encoding/frequency_encoding.h"
#include "reference/occupancy/occupancy_grid.h"
#include "reference/rays/rays.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

class Marcher : public test::GpuTest {};
class Scan : public test::GpuTest {};

struct TestRay {
  std::array<float, 3> o, d;
  float tNear = -1, tFar = -1;
};

TestRay clipped(std::array<float, 3> o, std::array<float, 3> d, const Aabb& box, float tMin = 0) {
  ref::Ray<float> r{o, d};
  ref::intersectAabb(r, box, tMin);
  return {o, d, r.tNear, r.tFar};
}

// Origins on a sphere around the box, aimed at random points inside it (plus some misses).
std::vector<TestRay> randomRays(uint32_t n, const Aabb& box, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
  std::vector<TestRay> out;
  for (uint32_t i = 0; i < n; ++i) {
    std::array<float, 3> o, target, d;
    float norm = 0;
    for (int k = 0; k < 3; ++k) {
      float c = 0.5f * (box.min[k] + box.max[k]), h = 0.5f * (box.max[k] - box.min[k]);
      o[k] = c + 3.0f * h * uni(rng);
      target[k] = c + (i % 10 == 0 ? 3.0f : 0.9f) * h * uni(rng);  // every tenth aims wide
      d[k] = target[k] - o[k];
      norm += d[k] * d[k];
    }
    for (auto& v : d) v /= std::sqrt(norm);
    out.push_back(clipped(o, d, box, 0.05f));
  }
  return out;
}

std::vector<float> packRays(const std::vector<TestRay>& rays) {
  std::vector<float> out;
  for (const auto& r : rays) out.insert(out.end(), {r.o[0], r.o[1], r.o[2], r.tNear, r.d[0], r.d[1], r.d[2], r.tFar});
  if (out.empty()) out.resize(8, -1.0f);
  return out;
}

struct MarchOut {
  std::vector<uint32_t> offsets, sampleRay, totals;
  std::vector<float> samples;  // 2 per sample
};

// `slotSamples` > 0: the marcher marches in one pass where the rays' slots fit (RayMarcher's slots).
MarchOut runMarch(Context& ctx, const std::vector<TestRay>& rays, nerf::OccupancyGrid& grid, const Aabb& box, float dt,
                  uint32_t maxSamples, uint32_t seed, bool jitter, uint64_t capacity = 0, uint32_t slotSamples = 0,
                  const nerf::ConeSteps& cone = {}) {
  uint32_t n = uint32_t(rays.size());
  if (capacity == 0) capacity = std::max<uint64_t>(uint64_t(n) * maxSamples, 1);
  auto rayBuf = gpu::Buffer::of(ctx, packRays(rays));
  gpu::Buffer offsets(ctx, (n + 1) * 4), samples(ctx, capacity * 8), sampleRay(ctx, capacity * 4), totals(ctx, 16);
  nerf::RayMarcher marcher(ctx, std::max(n, 1u), slotSamples);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    marcher.record(rec, {rayBuf, n}, grid, box, {dt, maxSamples, seed, jitter, cone},
                   {offsets, samples, sampleRay, totals});
  });
  MarchOut out{offsets.download<uint32_t>(n + 1), {}, totals.download<uint32_t>(4), {}};
  uint32_t total = out.offsets[n];
  out.samples = samples.download<float>(size_t(total) * 2);
  out.sampleRay = sampleRay.download<uint32_t>(total);
  return out;
}

ref::MarchParams paramsFor(const nerf::OccupancyGrid& grid, const Aabb& box, float dt, uint32_t maxSamples,
                           uint32_t seed, bool jitter) {
  ref::MarchParams p;
  p.boxMin = box.min;
  p.gridScale = ref::gridScale(grid.resolution(), box.min, box.max);
  p.resolution = grid.resolution();
  p.dt = dt;
  p.maxSamples = maxSamples;
  p.seed = seed;
  p.jitter = jitter;
  return p;
}

// Every ray's samples equal the reference's bit for bit: the shader and the float reference run
// the same `precise` float formulas, and cells are integers, so there is no tolerance to justify.
uint64_t expectMatchesReference(const MarchOut& out, const std::vector<TestRay>& rays, const ref::MarchParams& p,
                                const std::vector<uint32_t>& bits) {
  uint64_t total = 0;
  for (uint32_t r = 0; r < rays.size(); ++r) {
    const auto& ray = rays[r];
    auto expected = ref::marchRay<float>(ray.o, ray.d, ray.tNear, ray.tFar, r, p, bits);
    uint32_t first = out.offsets[r], count = out.offsets[r + 1] - first;
    EXPECT_EQ(count, expected.size()) << "ray " << r;
    if (count != expected.size()) continue;
    for (uint32_t i = 0; i < count; ++i) {
      EXPECT_EQ(out.samples[2 * (first + i)], expected[i].t) << "ray " << r << " sample " << i;
      EXPECT_EQ(out.samples[2 * (first + i) + 1], expected[i].delta) << "ray " << r << " sample " << i;
      EXPECT_EQ(out.sampleRay[first + i], r);
    }
    total += count;
  }
  EXPECT_EQ(out.offsets.back(), total);
  EXPECT_EQ(out.totals[0], total);
  return total;
}

void setBits(nerf::OccupancyGrid& grid, const std::vector<uint32_t>& bits) { grid.bits().upload(bits); }

std::vector<uint32_t> fullBits(const nerf::OccupancyGrid& grid) { return std::vector<uint32_t>(grid.numWords(), ~0u); }

// Cells occupied at random with probability `p`, or inside two balls (long empty runs to skip).
std::vector<uint32_t> randomBits(const nerf::OccupancyGrid& grid, double p, uint32_t seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution on(p);
  std::vector<uint32_t> bits(grid.numWords());
  for (uint32_t i = 0; i < grid.numCells(); ++i)
    if (on(rng)) ref::setBit(bits, i);
  return bits;
}

std::vector<uint32_t> ballBits(const nerf::OccupancyGrid& grid) {
  uint32_t r = grid.resolution();
  std::vector<uint32_t> bits(grid.numWords());
  for (uint32_t z = 0; z < r; ++z)
    for (uint32_t y = 0; y < r; ++y)
      for (uint32_t x = 0; x < r; ++x) {
        auto c = [&](uint32_t v) { return (v + 0.5) / r * 2 - 1; };
        double a = std::hypot(c(x) - 0.3, c(y) + 0.2, c(z) - 0.1), b = std::hypot(c(x) + 0.5, c(y) - 0.4, c(z) + 0.3);
        if (a < 0.35 || (b > 0.15 && b < 0.3)) ref::setBit(bits, ref::cellIndex(x, y, z, r));
      }
  return bits;
}

}  // namespace

// ---- Prefix sum ----

TEST_F(Scan, ExclusiveSumAtAwkwardSizes) {
  gpu::PrefixSum scan(ctx(), 1100001);
  std::mt19937 rng(2);
  // One block, exactly one block, one past, several blocks, and three levels (> 1024^2).
  for (uint32_t n : {1u, 5u, 1023u, 1024u, 1025u, 4097u, 70001u, 1100000u}) {
    std::vector<uint32_t> in(n);
    for (auto& v : in) v = rng() % 300;
    auto inBuf = gpu::Buffer::of(ctx(), in);
    gpu::Buffer out(ctx(), VkDeviceSize(n + 1) * 4);
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      scan.record(rec, inBuf, n, out, n + 1);
    });
    auto got = out.download<uint32_t>(n + 1);
    std::vector<uint32_t> expected(n + 1, 0);
    std::partial_sum(in.begin(), in.end(), expected.begin() + 1);
    for (uint32_t i = 0; i <= n; ++i) ASSERT_EQ(got[i], expected[i]) << "n " << n << " index " << i;
  }
}

TEST_F(Scan, ClampsOnlyTheFinalSums) {
  gpu::PrefixSum scan(ctx(), 5000);
  std::vector<uint32_t> in(4999, 3);
  auto inBuf = gpu::Buffer::of(ctx(), in);
  gpu::Buffer out(ctx(), 5000 * 4);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    scan.record(rec, inBuf, 4999, out, 5000, 7000);
  });
  auto got = out.download<uint32_t>(5000);
  for (uint32_t i = 0; i < 5000; ++i) ASSERT_EQ(got[i], std::min(3 * i, 7000u)) << i;
  gpu::Recorder rec(ctx());  // the size check throws before anything is recorded
  EXPECT_THROW(scan.record(rec, inBuf, 4999, out, 5001), Error);
}

// ---- March ----

TEST_F(Marcher, RandomRaysRandomOccupancyMatchReference) {
  Aabb box{{-1.5f, -0.5f, -1.0f}, {1.5f, 1.0f, 2.0f}};  // anisotropic cells
  nerf::OccupancyGrid grid(ctx(), 24);
  auto rays = randomRays(3000, box, 17);
  float dt = nerf::RayMarcher::defaultStep(box) * 4;
  uint64_t total = 0;
  for (int pattern = 0; pattern < 3; ++pattern) {
    auto bits = pattern == 0 ? randomBits(grid, 0.1, 5) : pattern == 1 ? randomBits(grid, 0.6, 6) : ballBits(grid);
    setBits(grid, bits);
    for (bool jitter : {false, true}) {
      auto out = runMarch(ctx(), rays, grid, box, dt, 4096, 99, jitter);
      total += expectMatchesReference(out, rays, paramsFor(grid, box, dt, 4096, 99, jitter), bits);
    }
  }
  EXPECT_GT(total, 100000u);  // the comparison saw real work
}

TEST_F(Marcher, EmptyGridGivesNoSamples) {
  Aabb box;
  nerf::OccupancyGrid grid(ctx(), 16);  // starts all empty
  auto rays = randomRays(500, box, 3);
  auto out = runMarch(ctx(), rays, grid, box, 0.01f, 64, 1, true);
  for (uint32_t v : out.offsets) EXPECT_EQ(v, 0u);
  EXPECT_EQ(out.totals[0], 0u);
  EXPECT_EQ(out.totals[1], 0u);  // an empty indirect dispatch
}

TEST_F(Marcher, FullGridIsTheUniformMarch) {
  Aabb box;
  nerf::OccupancyGrid grid(ctx(), 16);
  setBits(grid, fullBits(grid));
  auto rays = randomRays(400, box, 4);
  const float dt = 0.0137f;
  auto out = runMarch(ctx(), rays, grid, box, dt, 1000, 0, false);
  expectMatchesReference(out, rays, paramsFor(grid, box, dt, 1000, 0, false), fullBits(grid));
  uint32_t checked = 0, ambiguous = 0;
  for (uint32_t r = 0; r < rays.size(); ++r) {
    uint32_t first = out.offsets[r], count = out.offsets[r + 1] - first;
    if (rays[r].tNear < 0) {
      EXPECT_EQ(count, 0u);
      continue;
    }
    // In exact arithmetic: k = 0 .. ceil(length / dt) - 1. A length within float rounding of a
    // multiple of dt (t_k is off by ~1e-7 * 5 / dt = 4e-5 steps) could go either way: skip those.
    double length = double(rays[r].tFar) - rays[r].tNear, steps = length / dt;
    if (std::fabs(steps - std::round(steps)) < 1e-4) {
      ++ambiguous;
      continue;
    }
    ++checked;
    ASSERT_EQ(count, uint32_t(std::ceil(steps))) << "ray " << r;
    for (uint32_t i = 0; i < count; ++i) {
      double t = out.samples[2 * (first + i)], delta = out.samples[2 * (first + i) + 1];
      // t_k = t_near + k dt in float: ~1e-7 relative per operation on values up to ~5.
      EXPECT_TRUE(test::near(t, rays[r].tNear + double(i) * dt, 0, 2e-6));
      if (i + 1 < count)
        EXPECT_EQ(delta, double(dt));
      else
        EXPECT_TRUE(test::near(delta, rays[r].tFar - t, 0, 1e-6));  // the last segment ends at t_far
      EXPECT_LE(t + delta, rays[r].tFar * (1 + 1e-6));
    }
  }
  EXPECT_GT(checked, 300u);
  EXPECT_LT(ambiguous, 5u);
}

TEST_F(Marcher, RayParallelToCellFaces) {
  Aabb box;
  const uint32_t res = 8;
  nerf::OccupancyGrid grid(ctx(), res);
  auto bits = randomBits(grid, 0.3, 8);
  setBits(grid, bits);
  // Along +x exactly on the planes y = 0 and z = 0.5 (cell faces), along -y inside a cell row,
  // and along a face diagonal (two zero-free components crossing cell corners).
  std::vector<TestRay> rays = {clipped({-3, 0, 0.5f}, {1, 0, 0}, box), clipped({0.1f, 4, -0.3f}, {0, -1, 0}, box),
                               clipped({-2, -2, 0.25f}, {0.70710678f, 0.70710678f, 0}, box),
                               clipped({0.75f, 0.75f, -5}, {0, 0, 1}, box)};
  for (const auto& r : rays) ASSERT_GE(r.tNear, 0.0f);
  auto out = runMarch(ctx(), rays, grid, box, 0.02f, 1000, 0, false);
  EXPECT_GT(expectMatchesReference(out, rays, paramsFor(grid, box, 0.02f, 1000, 0, false), bits), 10u);
}

TEST_F(Marcher, LatticePointsExactlyOnCellFaces) {
  // R = 8 over [-1, 1]: cells 0.25 wide, dt = 1/16, so every fourth lattice point sits exactly on a
  // face (all values dyadic: the float arithmetic is exact). Cells x = 0, 2, 4, 6 of the row
  // (y, z) = (4, 4) are occupied. A point on a face belongs to the cell above it (floor), and the
  // point at x = 1 to the border cell 7.
  Aabb box;
  const uint32_t res = 8;
  nerf::OccupancyGrid grid(ctx(), res);
  std::vector<uint32_t> bits(grid.numWords());
  for (uint32_t x : {0u, 2u, 4u, 6u}) ref::setBit(bits, ref::cellIndex(x, 4, 4, res));
  setBits(grid, bits);
  std::vector<TestRay> rays = {{{-3, 0.125f, 0.125f}, {1, 0, 0}, 2, 4}, {{3, 0.125f, 0.125f}, {-1, 0, 0}, 2, 4}};
  auto out = runMarch(ctx(), rays, grid, box, 0.0625f, 1000, 0, false);
  for (uint32_t r = 0; r < 2; ++r) {
    std::vector<float> expected;
    for (uint32_t k = 0; k < 32; ++k) {
      double x = r == 0 ? -1 + k / 16.0 : 1 - k / 16.0;
      int cell = std::min(int(std::floor((x + 1) * 4)), 7);
      if (cell % 2 == 0) expected.push_back(2.0f + k / 16.0f);
    }
    ASSERT_EQ(out.offsets[r + 1] - out.offsets[r], expected.size()) << "ray " << r;
    for (size_t i = 0; i < expected.size(); ++i) {
      EXPECT_EQ(out.samples[2 * (out.offsets[r] + i)], expected[i]);
      EXPECT_EQ(out.samples[2 * (out.offsets[r] + i) + 1], 0.0625f);
    }
  }
  EXPECT_EQ(out.offsets[1], 16u);  // k = 0-3, 8-11, 16-19, 24-27
  EXPECT_EQ(out.offsets[2] - out.offsets[1], 15u);  // k = 5-8, 13-16, 21-24, 29-31
}

TEST_F(Marcher, RayStartingInsideTheBox) {
  Aabb box;
  nerf::OccupancyGrid grid(ctx(), 16);
  auto bits = ballBits(grid);
  setBits(grid, bits);
  std::vector<TestRay> rays;
  for (int i = 0; i < 50; ++i) {
    float a = 0.37f * i, b = 0.11f * i;
    rays.push_back(clipped({0.2f, -0.1f, 0.05f}, {std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b)},
                           box, 0.01f));
    ASSERT_FLOAT_EQ(rays.back().tNear, 0.01f);
  }
  auto out = runMarch(ctx(), rays, grid, box, 0.005f, 1000, 21, true);
  EXPECT_GT(expectMatchesReference(out, rays, paramsFor(grid, box, 0.005f, 1000, 21, true), bits), 100u);
  for (uint32_t r = 0; r < rays.size(); ++r)
    if (out.offsets[r + 1] > out.offsets[r]) EXPECT_GE(out.samples[2 * out.offsets[r]], 0.01f);
}

TEST_F(Marcher, MissingRaysGetNothing) {
  Aabb box;
  nerf::OccupancyGrid grid(ctx(), 8);
  setBits(grid, fullBits(grid));
  std::vector<TestRay> rays = {clipped({0, 0, 0}, {0, 0, 1}, box), clipped({5, 5, 5}, {1, 0, 0}, box),
                               clipped({0, 0, 0}, {1, 0, 0}, box)};
  ASSERT_LT(rays[1].tNear, 0.0f);
  rays.push_back({{0, 0, 0}, {0, 1, 0}, 0.5f, 0.5f});  // zero length
  auto out = runMarch(ctx(), rays, grid, box, 0.1f, 100, 0, false);
  EXPECT_EQ(out.offsets, (std::vector<uint32_t>{0, 10, 10, 20, 20}));
  EXPECT_EQ(out.sampleRay[9], 0u);
  EXPECT_EQ(out.sampleRay[10], 2u);
}

TEST_F(Marcher, CapPerRayKeepsTheFirstSamples) {
  Aabb box;
  nerf::OccupancyGrid grid(ctx(), 16);
  auto bits = randomBits(grid, 0.5, 12);
  setBits(grid, bits);
  auto rays = randomRays(300, box, 9);
  auto capped = runMarch(ctx(), rays, grid, box, 0.004f, 7, 5, true);
  auto full = runMarch(ctx(), rays, grid, box, 0.004f, 2000, 5, true);
  expectMatchesReference(capped, rays, paramsFor(grid, box, 0.004f, 7, 5, true), bits);
  uint32_t hitCap = 0;
  for (uint32_t r = 0; r < rays.size(); ++r) {
    uint32_t n = capped.offsets[r + 1] - capped.offsets[r], all = full.offsets[r + 1] - full.offsets[r];
    ASSERT_EQ(n, std::min(all, 7u));
    hitCap += n == 7;
    for (uint32_t i = 0; i < n; ++i)
      EXPECT_EQ(capped.samples[2 * (capped.offsets[r] + i)], full.samples[2 * (full.offsets[r] + i)]);
  }
  EXPECT_GT(hitCap, 100u);
}

TEST_F(Marcher, OverBudgetBatchKeepsItsFirstRays) {
  Aabb box;
  nerf::OccupancyGrid grid(ctx(), 8);
  setBits(grid, fullBits(grid));
  auto rays = randomRays(200, box, 10);
  auto all = runMarch(ctx(), rays, grid, box, 0.01f, 1000, 0, false);
  uint32_t capacity = all.offsets.back() / 3;
  auto cut = runMarch(ctx(), rays, grid, box, 0.01f, 1000, 0, false, capacity);
  EXPECT_EQ(cut.totals[0], capacity);
  for (uint32_t r = 0; r <= rays.size(); ++r) ASSERT_EQ(cut.offsets[r], std::min(all.offsets[r], capacity));
  for (uint32_t s = 0; s < capacity; ++s) {
    ASSERT_EQ(cut.samples[2 * s], all.samples[2 * s]);
    ASSERT_EQ(cut.sampleRay[s], all.sampleRay[s]);
  }
}

// A render's block marches once into each ray's slots and is packed after (march_slots,
// march_compact) where the two passes march every ray twice (march_count, march_write): the batch
// must be theirs bit for bit (offsets, samples, their rays, totals) on one grid and on cascades,
// plain and stretched (a bound, and the proposal's unbounded stretch), jittered, and cut by an
// output capacity that keeps only the first rays.
TEST_F(Marcher, SlotsMarchTheBatchOfTheTwoPasses) {
  const Aabb box{{-1.5f, -0.5f, -1.0f}, {1.5f, 1.0f, 2.0f}};
  const auto rays = randomRays(700, box, 31);
  const uint32_t n = uint32_t(rays.size()), most = 96;
  for (uint32_t cascades : {1u, 3u}) {
    nerf::OccupancyGrid grid(ctx(), 16, cascades);
    setBits(grid, randomBits(grid, 0.6, 40 + cascades));
    std::vector<float> density(grid.numCells());
    std::mt19937 rng(cascades);
    std::uniform_real_distribution<float> sigma(0.0f, 40.0f);
    for (float& d : density) d = sigma(rng);
    grid.density().upload(density);
    const float dt = nerf::RayMarcher::defaultStep(box) * 4;
    const std::vector<float> bounds =
        cascades == 1 ? std::vector<float>{0.0f} : std::vector<float>{0.0f, 0.05f, std::numeric_limits<float>::max()};
    for (float bound : bounds)
      for (bool jitter : {false, true}) {
        const nerf::ConeSteps cone{1.0f / 64.0f, dt * 8, bound, 8};
        const MarchOut full = runMarch(ctx(), rays, grid, box, dt, most, 7, jitter, 0, 0, cone);
        ASSERT_GT(full.offsets[n], 5u * n) << "cascades " << cascades << " bound " << bound;  // real work
        for (uint64_t capacity : {uint64_t(0), uint64_t(full.offsets[n] / 2)}) {
          const MarchOut two = capacity ? runMarch(ctx(), rays, grid, box, dt, most, 7, jitter, capacity, 0, cone) : full;
          const MarchOut one = runMarch(ctx(), rays, grid, box, dt, most, 7, jitter, capacity, n * most, cone);
          const std::string where = "cascades " + std::to_string(cascades) + " bound " + std::to_string(bound) +
                                    " jitter " + std::to_string(jitter) + " capacity " + std::to_string(capacity);
          EXPECT_EQ(one.offsets, two.offsets) << where;
          EXPECT_EQ(one.totals, two.totals) << where;
          EXPECT_EQ(one.samples, two.samples) << where;
          EXPECT_EQ(one.sampleRay, two.sampleRay) << where;
        }
      }
  }
}

TEST_F(Marcher, TotalsHoldIndirectDispatchArguments) {
  Aabb box;
  nerf::OccupancyGrid grid(ctx(), 8);
  setBits(grid, randomBits(grid, 0.4, 1));
  auto rays = randomRays(700, box, 2);
  auto out = runMarch(ctx(), rays, grid, box, 0.01f, 1000, 3, true);
  uint32_t total = out.offsets.back();
  ASSERT_GT(total, 1000u);
  EXPECT_EQ(out.totals[0], total);
  EXPECT_EQ(out.totals[1], (total + nerf::PackedLayout::kIndirectLocal - 1) / nerf::PackedLayout::kIndirectLocal);
  EXPECT_EQ(out.totals[2], 1u);
  EXPECT_EQ(out.totals[3], 1u);
}

TEST_F(Marcher, JitterShiftsTheLatticeWithinOneStep) {
  Aabb box;
  nerf::OccupancyGrid grid(ctx(), 8);
  setBits(grid, fullBits(grid));
  auto rays = randomRays(100, box, 6);
  auto plain = runMarch(ctx(), rays, grid, box, 0.02f, 1000, 0, false);
  auto jit = runMarch(ctx(), rays, grid, box, 0.02f, 1000, 42, true);
  expectMatchesReference(jit, rays, paramsFor(grid, box, 0.02f, 1000, 42, true), fullBits(grid));
  for (uint32_t r = 0; r < rays.size(); ++r) {
    if (rays[r].tNear < 0 || plain.offsets[r + 1] == plain.offsets[r]) continue;
    double u = ref::rng01(42, r, 0);
    EXPECT_EQ(plain.samples[2 * plain.offsets[r]], rays[r].tNear);
    EXPECT_TRUE(test::near(jit.samples[2 * jit.offsets[r]], rays[r].tNear + u * 0.02, 0, 1e-6));
  }
}

TEST_F(Marcher, RejectsBadArguments) {
  Aabb box;
  nerf::OccupancyGrid grid(ctx(), 8);
  nerf::RayMarcher marcher(ctx(), 10);
  gpu::Buffer rays(ctx(), 11 * 32), offsets(ctx(), 12 * 4), samples(ctx(), 64), sampleRay(ctx(), 64), totals(ctx(), 16);
  gpu::Recorder rec(ctx());
  rec.begin();
  const nerf::PackedSamples out{offsets, samples, sampleRay, totals};
  EXPECT_THROW(marcher.record(rec, {rays, 11}, grid, box, {0.01f, 8, 0, false}, out), Error);
  EXPECT_THROW(marcher.record(rec, {rays, 10}, grid, box, {0.0f, 8, 0, false}, out), Error);
  EXPECT_THROW(marcher.record(rec, {rays, 10}, grid, box, {NAN, 8, 0, false}, out), Error);
  EXPECT_THROW(marcher.record(rec, {rays, 10}, grid, box, {0.01f, 0, 0, false}, out), Error);
  Aabb flat{{0, 0, 0}, {1, 0, 1}};
  EXPECT_THROW(marcher.record(rec, {rays, 10}, grid, flat, {0.01f, 8, 0, false}, out), Error);
  gpu::Buffer shortOffsets(ctx(), 40);
  EXPECT_THROW(marcher.record(rec, {rays, 10}, grid, box, {0.01f, 8, 0, false}, {shortOffsets, samples, sampleRay, totals}),
               Error);
  rec.end();
}

// ---- Packed sample points ----

void packedPointsFollowSampleRays(Context& ctx, uint32_t chunkRows, bool midpoints = false) {
  Aabb box{{-2, -1, -1}, {2, 1, 3}};
  nerf::OccupancyGrid grid(ctx, 16);
  setBits(grid, randomBits(grid, 0.3, 4));
  auto rays = randomRays(300, box, 12);
  uint32_t n = uint32_t(rays.size()), capacity = 40000;
  auto rayBuf = gpu::Buffer::of(ctx, packRays(rays));
  gpu::Buffer offsets(ctx, (n + 1) * 4), samples(ctx, capacity * 8), sampleRay(ctx, capacity * 4),
      totals(ctx, 16), positions(ctx, capacity * 16), directions(ctx, capacity * 16);
  positions.upload(std::vector<float>(capacity * 4, 7.0f));  // sentinel past the batch
  nerf::RayMarcher marcher(ctx, n);
  nerf::PackedSamplePoints points(ctx, chunkRows);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    marcher.record(rec, {rayBuf, n}, grid, box, {0.02f, 256, 8, true}, {offsets, samples, sampleRay, totals});
    points.record(rec, capacity, rayBuf, {offsets, samples, sampleRay, totals}, box, {positions, directions}, midpoints);
  });
  uint32_t total = totals.download<uint32_t>(1)[0];
  ASSERT_GT(total, 1000u);
  ASSERT_LT(total, capacity);
  auto s = samples.download<float>(size_t(total) * 2);
  auto sr = sampleRay.download<uint32_t>(total);
  auto pos = positions.download<float>(size_t(capacity) * 4);
  auto dir = directions.download<float>(size_t(total) * 4);
  for (uint32_t i = 0; i < total; ++i) {
    const auto& r = rays[sr[i]];
    std::array<double, 3> o{r.o[0], r.o[1], r.o[2]}, d{r.d[0], r.d[1], r.d[2]};
    const double t = midpoints ? double(s[2 * i]) + 0.5 * double(s[2 * i + 1]) : double(s[2 * i]);
    auto p = ref::samplePosition<double>(o, d, t, box);
    for (int k = 0; k < 3; ++k) {
      // o + t d with |o|, t up to ~10, then an affine map with O(1) factors: a few float roundings
      // of values up to ~10, so ~1e-6 absolute; the result lies in [-1, 1] up to that rounding.
      EXPECT_TRUE(test::near(pos[4 * i + k], p[k], 0, 4e-6));
      EXPECT_LE(std::fabs(pos[4 * i + k]), 1.0 + 1e-5);
      EXPECT_EQ(dir[4 * i + k], r.d[k]);
    }
  }
  for (uint32_t i = total; i < capacity; ++i) ASSERT_EQ(pos[4 * i], 7.0f) << "wrote past the batch at " << i;
}

// One dispatch, and chunks of 4096 samples (10 for this batch's capacity, the last ones past the
// total): each chunk's samples must land at their own rows.
TEST_F(Marcher, PackedPointsFollowSampleRays) {
  for (uint32_t chunkRows : {nerf::PackedSamplePoints::kChunkRows, 4096u}) {
    SCOPED_TRACE(chunkRows);
    packedPointsFollowSampleRays(ctx(), chunkRows);
  }
}

// At the middle of each sample's interval (the proposal's candidates, which stand for several steps).
TEST_F(Marcher, PackedPointsAtMidpoints) { packedPointsFollowSampleRays(ctx(), 4096u, true); }

// Occupancy grid kernels (shaders/occupancy/occupancy_*.comp) against the CPU reference
// (tests/reference/occupancy/occupancy_grid.h). Nothing here is differentiated, so there is no gradient check.
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
#include "nerf/occupancy/occupancy_grid.h"
#include "reference/occupancy/occupancy_grid.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

class Occupancy : public test::GpuTest {};

struct Points {
  std::vector<float> positions;  // 4 per point
  std::vector<uint32_t> cells;
};

Points runPoints(Context& ctx, nerf::OccupancyGrid& grid, uint32_t seed, bool random, uint32_t count) {
  gpu::Buffer pos(ctx, VkDeviceSize(count) * 16), cells(ctx, VkDeviceSize(count) * 4);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    if (random)
      grid.recordRandomCellPoints(rec, seed, count, pos, cells);
    else
      grid.recordAllCellPoints(rec, seed, pos, cells);
  });
  return {pos.download<float>(size_t(count) * 4), cells.download<uint32_t>(count)};
}

void runUpdate(Context& ctx, nerf::OccupancyGrid& grid, const std::vector<uint32_t>& cells,
               const std::vector<float>& density, float decay, float threshold) {
  auto cellBuf = gpu::Buffer::of(ctx, cells.empty() ? std::vector<uint32_t>{0} : cells);
  auto denBuf = gpu::Buffer::of(ctx, density.empty() ? std::vector<float>{0} : density);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    grid.recordUpdate(rec, {cellBuf, denBuf, uint32_t(cells.size())}, {decay, threshold});
  });
}

}  // namespace

TEST_F(Occupancy, AllCellPointsLieInTheirCells) {
  const uint32_t r = 12, seed = 77;  // 1728 cells: not a multiple of 32 or of a workgroup
  nerf::OccupancyGrid grid(ctx(), r);
  auto pts = runPoints(ctx(), grid, seed, false, grid.numCells());
  for (uint32_t j = 0; j < grid.numCells(); ++j) {
    ASSERT_EQ(pts.cells[j], j);
    auto p = ref::cellPointPosition<double>(j, r, seed, j);
    uint32_t c[3] = {j % r, (j / r) % r, j / (r * r)};
    for (int k = 0; k < 3; ++k) {
      // (c + u) * 2/R - 1 with O(1) terms: a few float roundings, ~1e-7 absolute.
      EXPECT_TRUE(test::near(pts.positions[4 * j + k], p[k], 0, 4e-7));
      double lo = -1.0 + 2.0 * c[k] / r, hi = -1.0 + 2.0 * (c[k] + 1) / r;
      EXPECT_GE(pts.positions[4 * j + k], lo - 1e-6);
      EXPECT_LE(pts.positions[4 * j + k], hi + 1e-6);
    }
    EXPECT_EQ(pts.positions[4 * j + 3], 0.0f);
  }
}

TEST_F(Occupancy, RandomCellPointsFollowCounterRng) {
  const uint32_t r = 16, seed = 5, count = 3000;
  nerf::OccupancyGrid grid(ctx(), r);
  auto pts = runPoints(ctx(), grid, seed, true, count);
  std::vector<int> perOctant(8);
  for (uint32_t j = 0; j < count; ++j) {
    uint32_t cell = ref::cellPointCell(r, seed, j, true);
    ASSERT_EQ(pts.cells[j], cell);
    auto p = ref::cellPointPosition<double>(cell, r, seed, j);
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(test::near(pts.positions[4 * j + k], p[k], 0, 4e-7));
    perOctant[(pts.positions[4 * j] > 0) + 2 * (pts.positions[4 * j + 1] > 0) + 4 * (pts.positions[4 * j + 2] > 0)]++;
  }
  for (int n : perOctant) EXPECT_GT(n, 250);  // uniform over the box: 375 expected per octant
}

TEST_F(Occupancy, EmaUpdateMatchesReference) {
  // 1000 cells: the last bit word is partial; 343: and so is its last vec4 (the kernel reads 4 cells
  // at a time from buffers padded to whole words).
  for (uint32_t r : {10u, 7u}) {
    SCOPED_TRACE(r);
    nerf::OccupancyGrid grid(ctx(), r);
    std::vector<float> density(grid.numCells(), 0.0f);
    std::vector<uint32_t> bits;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    const float decay = 0.95f, threshold = 0.3f;
    for (int update = 0; update < 4; ++update) {
      // Random subset with repeats (several points per cell: the largest must win) and hard values.
      std::vector<uint32_t> cells;
      std::vector<float> measured;
      for (uint32_t j = 0; j < grid.numCells() * 3 / 2; ++j) {  // 1.5 points a cell
        cells.push_back(rng() % grid.numCells());
        float v = uni(rng);
        measured.push_back(v * v);
      }
      if (update == 1) {
        measured[0] = std::numeric_limits<float>::quiet_NaN();
        measured[1] = -2.0f;
        measured[2] = std::numeric_limits<float>::infinity();
        measured[3] = 1e30f;
      }
      runUpdate(ctx(), grid, cells, measured, decay, threshold);
      ref::updateGrid(density, bits, cells, measured, decay, threshold);
      auto gd = grid.density().download<float>(grid.numCells());
      auto gb = grid.bits().download<uint32_t>(grid.numWords());
      for (uint32_t i = 0; i < grid.numCells(); ++i) {
        // max() and one float multiply, in the same order: bit-identical.
        ASSERT_EQ(gd[i], density[i]) << "cell " << i << " update " << update;
        ASSERT_TRUE(std::isfinite(gd[i]));
        ASSERT_EQ(ref::bitSet(gb, i), ref::bitSet(bits, i)) << "cell " << i;
      }
    }
    // The update was not vacuous: at least 5% of the cells on, and 5% off.
    uint32_t on = ref::countOccupied(bits, grid.numCells());
    EXPECT_GT(on, grid.numCells() / 20);
    EXPECT_LT(on, grid.numCells() - grid.numCells() / 20);
  }
}

TEST_F(Occupancy, UnsampledCellsDecayAndTurnOff) {
  nerf::OccupancyGrid grid(ctx(), 4);
  std::vector<uint32_t> all(64);
  for (uint32_t i = 0; i < 64; ++i) all[i] = i;
  runUpdate(ctx(), grid, all, std::vector<float>(64, 1.0f), 0.5f, 0.3f);
  EXPECT_FLOAT_EQ(grid.occupiedFraction(), 1.0f);
  runUpdate(ctx(), grid, {}, {}, 0.5f, 0.3f);  // nothing measured: d = 0.5, still above 0.3
  EXPECT_FLOAT_EQ(grid.occupiedFraction(), 1.0f);
  runUpdate(ctx(), grid, {7}, {0.9f}, 0.5f, 0.3f);  // d = 0.25 everywhere but cell 7
  auto d = grid.density().download<float>(64);
  EXPECT_EQ(d[7], 0.9f);
  EXPECT_EQ(d[8], 0.25f);
  EXPECT_FLOAT_EQ(grid.occupiedFraction(), 1.0f / 64.0f);
  EXPECT_EQ(grid.bits().download<uint32_t>(2)[0], 1u << 7);
}

TEST_F(Occupancy, BitPackingIsLinearCellOrder) {
  const uint32_t r = 8;
  nerf::OccupancyGrid grid(ctx(), r);
  // One hot cell at (x, y, z) = (3, 5, 6): index 3 + 8 (5 + 8 * 6) = 427, word 13, bit 11.
  std::vector<uint32_t> cells = {ref::cellIndex(3, 5, 6, r)};
  ASSERT_EQ(cells[0], 427u);
  runUpdate(ctx(), grid, cells, {2.0f}, 1.0f, 1.0f);
  auto bits = grid.bits().download<uint32_t>(grid.numWords());
  for (uint32_t w = 0; w < grid.numWords(); ++w) EXPECT_EQ(bits[w], w == 13 ? 1u << 11 : 0u) << "word " << w;
  // The jittered point for that cell lies inside it in the normalised box: x in [-0.25, 0).
  auto p = ref::cellPointPosition<double>(427, r, 9, 0);
  EXPECT_GE(p[0], -0.25);
  EXPECT_LT(p[0], 0.0);
  EXPECT_GE(p[1], 0.25);
  EXPECT_GE(p[2], 0.5);
}

TEST_F(Occupancy, OccupiedFractionCountsOnlyRealCells) {
  const uint32_t r = 7;  // 343 cells: 11 words, 9 stray bits in the last one
  nerf::OccupancyGrid grid(ctx(), r);
  EXPECT_EQ(grid.occupiedFraction(), 0.0f);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    grid.recordMarkAllOccupied(rec);
  });
  EXPECT_EQ(grid.occupiedFraction(), 1.0f);
  // A random pattern uploaded directly, counted against the reference.
  std::mt19937 rng(11);
  std::vector<uint32_t> bits(grid.numWords());
  for (auto& w : bits) w = rng();
  grid.bits().upload(bits);
  double expected = double(ref::countOccupied(bits, grid.numCells())) / grid.numCells();
  EXPECT_NEAR(grid.occupiedFraction(), expected, 1e-7);  // float of an exact ratio
}

TEST_F(Occupancy, LargeGridFraction) {
  // The default resolution: 2^21 cells over several workgroups of the count kernel.
  nerf::OccupancyGrid grid(ctx(), 128);
  std::vector<uint32_t> bits(grid.numWords());
  std::mt19937 rng(1);
  for (auto& w : bits) w = rng() & rng() & rng();  // ~1/8 of the bits
  grid.bits().upload(bits);
  double expected = double(ref::countOccupied(bits, grid.numCells())) / grid.numCells();
  EXPECT_NEAR(grid.occupiedFraction(), expected, 1e-7);
}

TEST_F(Occupancy, RejectsBadArguments) {
  EXPECT_THROW(nerf::OccupancyGrid(ctx(), 0), Error);
  EXPECT_THROW(nerf::OccupancyGrid(ctx(), 300), Error);
  nerf::OccupancyGrid grid(ctx(), 4);
  gpu::Buffer small(ctx(), 16);
  gpu::Recorder rec(ctx());
  rec.begin();
  EXPECT_THROW(grid.recordUpdate(rec, {small, small, 4}, {1.5f, 0.1f}), Error);
  EXPECT_THROW(grid.recordUpdate(rec, {small, small, 4}, {0.9f, -1.0f}), Error);
  EXPECT_THROW(grid.recordUpdate(rec, {small, small, 5}, {0.9f, 0.1f}), Error);
  EXPECT_THROW(grid.recordAllCellPoints(rec, 0, small, small), Error);
  rec.end();
  EXPECT_FLOAT_EQ(nerf::OccupancyGrid::densityThreshold(0.01f, 0.002f), 5.0f);
}

TEST(OccupancyDecay, EveryCellDecaysAsMuchBetweenTwoOfItsMeasurements) {
  using nerf::OccupancyGrid;
  // A quarter of the cells or more a time: instant-ngp's decay per update, unchanged.
  EXPECT_EQ(OccupancyGrid::decayFor(0.95f, 1u << 16, 1u << 18), 0.95f);
  EXPECT_EQ(OccupancyGrid::decayFor(0.95f, 1u << 18, 1u << 18), 0.95f);
  EXPECT_EQ(OccupancyGrid::decayFor(0.95f, 1u << 18, 1u << 17), 0.95f);
  // Fewer: a cell is measured once in cells / measured updates on average, and over those it must
  // decay as a cell measured once in 4 updates does (0.95^4). The factor is a float: its rounding
  // (relative 6e-8) raised to the 256th power (2^24 cells) is a relative 1.5e-5 of 0.81.
  for (uint32_t cells : {1u << 19, 1u << 21, 1u << 24}) {
    const uint32_t measured = 1u << 16;
    const double perUpdate = OccupancyGrid::decayFor(0.95f, measured, cells);
    EXPECT_LT(perUpdate, 1.0);
    EXPECT_GT(perUpdate, 0.95);
    EXPECT_NEAR(std::pow(perUpdate, double(cells) / measured), std::pow(0.95, 4.0), 3e-5) << cells << " cells";
  }
}

TEST_F(Occupancy, StridedDensityReadsTheChosenComponent) {
  // The fast pipeline feeds sigma straight out of the field's vec4 (r, g, b, sigma): stride 4,
  // component 3 must give exactly what the same densities give packed one per point.
  const uint32_t r = 8;
  std::vector<uint32_t> cells;
  std::vector<float> packed, field;
  for (uint32_t j = 0; j < 700; ++j) {
    cells.push_back((j * 37u) % (r * r * r));
    const float sigma = float((j * 13u) % 29u) * 0.1f;
    packed.push_back(sigma);
    // Decoys in the other components: reading the wrong one changes the bits.
    field.insert(field.end(), {5.0f - sigma, 100.0f, 0.0f, sigma});
  }
  nerf::OccupancyGrid one(ctx(), r), four(ctx(), r);
  runUpdate(ctx(), one, cells, packed, 0.5f, 1.2f);
  auto cellBuf = gpu::Buffer::of(ctx(), cells);
  auto fieldBuf = gpu::Buffer::of(ctx(), field);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    four.recordUpdate(rec, {cellBuf, fieldBuf, uint32_t(cells.size()), 4, 3}, {0.5f, 1.2f});
  });
  EXPECT_EQ(one.density().download<float>(one.numCells()), four.density().download<float>(four.numCells()));
  EXPECT_EQ(one.bits().download<uint32_t>(one.numWords()), four.bits().download<uint32_t>(four.numWords()));
  EXPECT_GT(one.occupiedFraction(), 0.0f);
  EXPECT_LT(one.occupiedFraction(), 1.0f);
  gpu::Recorder rec(ctx());  // the component check throws before anything is recorded
  EXPECT_THROW(four.recordUpdate(rec, {cellBuf, fieldBuf, 4, 4, 4}, {0.5f, 1.2f}), Error);
}

// The threshold cap of a young field: the grid's mean density, computed on the device, against the
// CPU's mean in double; the update then turns on exactly the cells above min(threshold, mean).
TEST_F(Occupancy, DeviceMeanDensityCapsTheThreshold) {
  // 8000 cells: workgroups of a few cells each; 3 x 64^3: many strided
  // passes per lane in every workgroup, and cells past the first workgroup's share.
  // 343 cells: the last vec4 the kernels read is partial.
  for (auto [r, cascades] : {std::pair{20u, 1u}, std::pair{7u, 1u}, std::pair{64u, 3u}}) {
    SCOPED_TRACE(r);
    nerf::OccupancyGrid grid(ctx(), r, cascades);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    std::vector<float> density(grid.numCells());
    for (float& d : density) d = 0.05f * uni(rng) * uni(rng);
    density[7] = std::numeric_limits<float>::quiet_NaN();  // a non-finite density counts as 0
    density[9] = -1.0f;                                    // so does a cell no camera sees
    density[grid.numCells() - 2] = std::numeric_limits<float>::infinity();  // and an infinite one
    grid.density().upload(density);
    double sum = 0;
    for (float d : density) sum += std::isfinite(d) ? std::max(d, 0.0f) : 0.0f;
    const double mean = sum / density.size();

    const float threshold = 1.0f;  // far above every density: the mean decides
    std::vector<uint32_t> cells{3, 4, 5};
    std::vector<float> measured{0.5f, 0.0f, 0.02f};
    auto cellBuf = gpu::Buffer::of(ctx(), cells);
    auto denBuf = gpu::Buffer::of(ctx(), measured);
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      grid.recordUpdate(rec, {cellBuf, denBuf, uint32_t(cells.size()), 1, 0}, {1.0f, threshold, true});
    });
    const float deviceMean = grid.meanDensity().download<float>(1)[0];
    EXPECT_NEAR(deviceMean, mean, 1e-5 * mean);

    std::vector<float> refDensity = density;
    refDensity[7] = 0.0f;  // the EMA stores a NaN as 0 (its max with a fresh 0)
    std::vector<uint32_t> bits;
    ref::updateGrid(refDensity, bits, cells, measured, 1.0f, std::min(threshold, deviceMean));
    auto gb = grid.bits().download<uint32_t>(grid.numWords());
    uint32_t on = 0;
    for (uint32_t i = 0; i < grid.numCells(); ++i) {
      ASSERT_EQ(ref::bitSet(gb, i), ref::bitSet(bits, i)) << "cell " << i;
      on += ref::bitSet(bits, i);
    }
    EXPECT_GT(on, 100u);  // the cap was not vacuous: about half the cells lie above the mean
    EXPECT_LT(on, grid.numCells() - 100u);

    // The next update's mean comes from the sums of 32 cells the EMA wrote (nothing has taken the
    // densities to write since): the mean of the densities as that EMA left them.
    const std::vector<float> after = std::as_const(grid).density().download<float>(grid.numCells());
    double sumAfter = 0;
    for (float d : after) sumAfter += std::isfinite(d) ? std::max(d, 0.0f) : 0.0f;
    const double meanAfter = sumAfter / after.size();
    ASSERT_NE(float(meanAfter), deviceMean);  // the fresh 0.5 moved it: a stale mean would show
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
      grid.recordUpdate(rec, {cellBuf, denBuf, uint32_t(cells.size()), 1, 0}, {1.0f, threshold, true});
    });
    EXPECT_NEAR(grid.meanDensity().download<float>(1)[0], meanAfter, 1e-5 * meanAfter);
  }
}

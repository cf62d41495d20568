// A mesh export's density grid sampled only near the occupancy grid's occupied cells: on an
// analytic field whose occupied region is known, the surface there is the whole grid's, and a
// surface the occupancy grid does not mark is skipped.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/mesh/density_grid.h"
#include "nerf/mesh/marching_cubes.h"
#include "nerf/mesh/sample_blocks.h"
#include "reference/mesh/marching_cubes.h"
#include "support/gpu_test.h"

using namespace vknerf;

namespace {

using Field = std::function<float(float, float, float)>;

// A density that falls from 2 at `c` to 0 at distance 2r (the surface at 1 is the sphere of radius
// r) and stays 0 beyond: nothing outside the ball of radius 2r.
float cone(float x, float y, float z, const std::array<float, 3>& c, float r) {
  const float d = std::sqrt((x - c[0]) * (x - c[0]) + (y - c[1]) * (y - c[1]) + (z - c[2]) * (z - c[2]));
  return std::max(0.0f, 2.0f - d / r);
}
constexpr std::array<float, 3> kSeenCentre{-0.45f, 0.0f, 0.05f}, kUnseenCentre{0.75f, 0.6f, 0.6f};
constexpr float kSeenRadius = 0.2f, kUnseenRadius = 0.12f;

// The occupancy a render would have learnt of the seen ball: R^3 cells over the box [-1, 1]^3, a
// cell occupied where it meets the ball's support (radius 2r).
nerf::OccupancyBits occupancyOfSeenBall(uint32_t r) {
  nerf::OccupancyBits bits{r, 1, std::vector<uint32_t>((r * r * r + 31) / 32, 0u)};
  const float side = 2.0f / float(r);
  for (uint32_t i = 0; i < r * r * r; ++i) {
    const uint32_t idx[3] = {i % r, (i / r) % r, i / (r * r)};
    float d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const float lo = -1 + side * idx[k], hi = lo + side;
      const float nearest = std::clamp(kSeenCentre[k], lo, hi);
      d2 += (nearest - kSeenCentre[k]) * (nearest - kSeenCentre[k]);
    }
    if (d2 < 4 * kSeenRadius * kSeenRadius) bits.words[i >> 5] |= 1u << (i & 31u);
  }
  return bits;
}

class SampleBlocks : public test::GpuTest {
 protected:
  // The grid through DensityGridSampler: the listed blocks' positions from the device, `field`
  // evaluated there on the host (as the model's query would), the densities scattered back.
  ref::TriangleMesh surface(const ref::GridLayout& g, const nerf::SampleBlocks& blocks, const Field& field) {
    const Aabb box;  // [-1, 1]^3: normalised and world coordinates agree
    gpu::Buffer ids(ctx(), std::max<VkDeviceSize>(4, blocks.ids.size() * 4));
    ids.upload(blocks.ids);
    nerf::DensityGridSampler sampler(ctx(), g, blocks, ids);
    const uint32_t slots = uint32_t(sampler.slots());
    gpu::Buffer positions(ctx(), std::max<VkDeviceSize>(16, VkDeviceSize(slots) * 16));
    gpu::Buffer values(ctx(), std::max<VkDeviceSize>(16, VkDeviceSize(slots) * 16));
    gpu::Buffer grid(ctx(), g.points() * 4);
    grid.zero();
    gpu::Recorder rec(ctx());
    if (slots) {
      rec.begin();
      sampler.recordPositions(rec, box, 0, slots, positions);
      rec.end();
      rec.submitAndWait();
      auto p = positions.download<float>(size_t(slots) * 4);
      for (size_t i = 0; i < slots; ++i) p[4 * i + 3] = field(p[4 * i], p[4 * i + 1], p[4 * i + 2]);
      values.upload(p);
      rec.begin();
      sampler.recordDensities(rec, values, 0, slots, grid);
      rec.end();
      rec.submitAndWait();
    }
    nerf::MarchingCubes mc(ctx());
    return mc.extract(grid, g, 1.0f);
  }
};

ref::GridLayout cube(uint32_t n) {
  ref::GridLayout g;
  const float h = 2.0f / float(n - 1);
  g.n = {n, n, n};
  g.origin = {-1, -1, -1};
  g.spacing = {h, h, h};
  return g;
}

TEST_F(SampleBlocks, OccupiedOnlyKeepsTheSurfaceWhereTheFieldIsOccupied) {
  const ref::GridLayout g = cube(27);  // 7 blocks a side, the last one partly past the grid
  const Field seen = [](float x, float y, float z) { return cone(x, y, z, kSeenCentre, kSeenRadius); };
  const Field both = [&](float x, float y, float z) {
    return seen(x, y, z) + cone(x, y, z, kUnseenCentre, kUnseenRadius);
  };
  const nerf::SampleBlocks all = nerf::allSampleBlocks(g);
  const nerf::SampleBlocks occupied = nerf::occupiedSampleBlocks(g, Aabb{}, occupancyOfSeenBall(10));
  ASSERT_EQ(all.ids.size(), 7u * 7u * 7u);
  ASSERT_GT(occupied.ids.size(), 0u);
  EXPECT_LT(occupied.ids.size(), all.ids.size() / 3);

  const ref::TriangleMesh seenWhole = surface(g, all, seen);
  const ref::TriangleMesh bothWhole = surface(g, all, both);
  const ref::TriangleMesh bothOccupied = surface(g, occupied, both);
  ASSERT_GT(seenWhole.triangles.size(), 0u);
  EXPECT_GT(bothWhole.triangles.size(), seenWhole.triangles.size());  // the unseen ball is there too
  // Sampling near the occupied cells: exactly the seen ball's surface, the unseen one skipped.
  EXPECT_EQ(bothOccupied.positions, seenWhole.positions);
  EXPECT_EQ(bothOccupied.triangles, seenWhole.triangles);
}

TEST_F(SampleBlocks, NothingOccupiedSamplesNothing) {
  const ref::GridLayout g = cube(9);
  nerf::OccupancyBits none{4, 2, std::vector<uint32_t>(4, 0u)};
  EXPECT_TRUE(nerf::occupiedSampleBlocks(g, Aabb{}, none).ids.empty());
  // An outer cascade's occupied corner cell reaches only the grid's corner block.
  none.words[(64 + 0) >> 5] |= 1u << ((64 + 0) & 31u);
  const auto corner = nerf::occupiedSampleBlocks(g, Aabb{}, none);
  ASSERT_EQ(corner.ids.size(), 1u);
  EXPECT_EQ(corner.ids[0], 0u);
}

}  // namespace

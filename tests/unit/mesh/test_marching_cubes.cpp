// Marching cubes: the CPU reference (tests/reference/mesh/) on analytic fields, and the device stage
// (src/nerf/mesh/, shaders/mesh/mc_*.comp) against it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <random>

#include "gpu/memory/buffer.h"
#include "nerf/mesh/marching_cubes.h"
#include "reference/mesh/marching_cubes.h"
#include "support/gpu_test.h"
#include "support/mesh_checks.h"

using namespace vknerf;

namespace {

constexpr float kSurface = 1.0f;  // the fields below cross it on the analytic surface

TEST(MarchingCubesTable, EveryCaseIsClosedAroundTheCube) {
  // The complement of a case cuts the same edges with the opposite orientation; the empty and full
  // cases have no triangles.
  const auto& table = ref::marchingCubesTable();
  EXPECT_EQ(table[0], 0u);
  EXPECT_EQ(table[255 * ref::kMcTableStride], 0u);
  for (uint32_t config = 1; config < 255; ++config) EXPECT_GE(table[config * ref::kMcTableStride], 1u) << config;
}

TEST(MarchingCubesReference, BallIsClosedOutwardAndOnTheSphere) {
  const uint32_t n = 33;
  const double r = 0.7;
  auto grid = test::sampledGrid(n, [&](double x, double y, double z) { return test::ballDensity(x, y, z, r); });
  auto mesh = ref::marchingCubes(grid, kSurface);
  ASSERT_GT(mesh.triangles.size(), 0u);
  EXPECT_EQ(test::closedAndOriented(mesh.triangles), "");
  const double h = grid.spacing[0];
  // |x| is convex along a grid edge, not linear, so the interpolated crossing lies off the sphere by
  // the edge's sag, O(h^2 / r) (here ~7e-4 of h = 0.0625); h^2 / r bounds it with room.
  for (size_t v = 0; v < mesh.positions.size(); v += 3) {
    const double d = std::hypot(mesh.positions[v], mesh.positions[v + 1], mesh.positions[v + 2]);
    EXPECT_NEAR(d, r, h * h / r) << "vertex " << v / 3;
  }
  const double volume = test::signedVolume(mesh.positions, mesh.triangles);
  const double exact = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  // Inscribed: every triangle's plane lies within h^2 / (2 r) of the sphere (a chord of length at
  // most sqrt(2) h sags by h^2 / (4 r)), so the volume lost is below area * h^2 / (2 r).
  EXPECT_GT(volume, 0);
  EXPECT_LE(volume, exact);
  EXPECT_GE(volume, exact - 4 * std::numbers::pi * r * r * h * h / (2 * r));
}

TEST(MarchingCubesReference, BoxIsClosedOutwardAndOnTheFaces) {
  const uint32_t n = 25;
  const std::array<double, 3> half{0.55, 0.3, 0.72};
  auto grid = test::sampledGrid(n, [&](double x, double y, double z) { return test::boxDensity(x, y, z, half); });
  auto mesh = ref::marchingCubes(grid, kSurface);
  ASSERT_GT(mesh.triangles.size(), 0u);
  EXPECT_EQ(test::closedAndOriented(mesh.triangles), "");
  const double h = grid.spacing[0];
  // Away from the box's edges the density is linear along every grid edge: vertices fall on the
  // faces; near an edge or corner the max() bends within one cell, so a vertex is at most h off.
  for (size_t v = 0; v < mesh.positions.size(); v += 3) {
    double outside = -1e9;  // signed distance to the box surface (>0 outside), max-norm style
    for (int k = 0; k < 3; ++k) outside = std::max(outside, std::fabs(mesh.positions[v + k]) - half[k]);
    EXPECT_LE(std::fabs(outside), h) << "vertex " << v / 3;
  }
  const double volume = test::signedVolume(mesh.positions, mesh.triangles);
  const double exact = 8 * half[0] * half[1] * half[2];
  // The faces are exact; what is cut or added stays within one cell of the box's edges (total edge
  // length 4 (a + b + c), 8 of them in the box's full perimeter), h^2 each per unit length.
  const double edgeLength = 8 * (half[0] + half[1] + half[2]);
  EXPECT_NEAR(volume, exact, edgeLength * h * h);
}

TEST(MarchingCubesReference, NoiseIsClosedAndOriented) {
  // Every case, ambiguous faces included: the neighbours of a face must join its crossings alike.
  // The outer layer stays outside so the surface cannot leave the grid.
  for (uint32_t seed = 1; seed <= 8; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 2.0f);
    auto grid = test::sampledGrid(12, [&](double x, double y, double z) {
      const bool border = std::max({std::fabs(x), std::fabs(y), std::fabs(z)}) > 0.99;
      return border ? 0.0f : u(rng);
    });
    auto mesh = ref::marchingCubes(grid, kSurface);
    ASSERT_GT(mesh.triangles.size(), 300u);
    EXPECT_EQ(test::closedAndOriented(mesh.triangles), "") << "seed " << seed;
    EXPECT_GT(test::signedVolume(mesh.positions, mesh.triangles), 0) << "seed " << seed;
  }
}

class MarchingCubesDevice : public test::GpuTest {
 protected:
  // The device's mesh of `grid` equals the reference's: the same triangles over the same vertex
  // ids, and positions equal up to float rounding.
  void expectSameAsReference(const ref::DensityGrid& grid, uint32_t chunk) {
    nerf::MarchingCubes mc(ctx(), chunk);
    auto values = gpu::Buffer::of(ctx(), grid.values);
    auto got = mc.extract(values, grid, kSurface);
    auto want = ref::marchingCubes(grid, kSurface);
    ASSERT_EQ(got.triangles, want.triangles);
    ASSERT_EQ(got.positions.size(), want.positions.size());
    // Same operations (the shader's are `precise`), but GLSL's division may be off by 2.5 ulp:
    // t by ~3e-7, the position by that times the spacing, next to rounding the sum (|p| <= 1).
    for (size_t i = 0; i < got.positions.size(); ++i)
      ASSERT_NEAR(got.positions[i], want.positions[i], 4e-7) << "coordinate " << i;
  }
};

TEST_F(MarchingCubesDevice, BallMatchesTheReferenceOverSeveralChunks) {
  auto grid = test::sampledGrid(33, [](double x, double y, double z) { return test::ballDensity(x, y, z, 0.7); });
  expectSameAsReference(grid, 8192);  // 107,811 edges and 32,768 cells: 14 and 4 chunks
}

TEST_F(MarchingCubesDevice, BoxMatchesTheReferenceInOneChunk) {
  auto grid = test::sampledGrid(25, [](double x, double y, double z) { return test::boxDensity(x, y, z, {0.55, 0.3, 0.72}); });
  expectSameAsReference(grid, 0);
}

TEST_F(MarchingCubesDevice, NoiseMatchesTheReference) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 2.0f);
  auto grid = test::sampledGrid(20, [&](double, double, double) { return u(rng); });
  grid.values[5] = std::numeric_limits<float>::quiet_NaN();  // outside, and a vertex mid-edge
  expectSameAsReference(grid, 1024);
}

TEST_F(MarchingCubesDevice, EmptyGridGivesNoTriangles) {
  nerf::MarchingCubes mc(ctx());
  auto grid = test::sampledGrid(4, [](double, double, double) { return 0.0f; });
  auto values = gpu::Buffer::of(ctx(), grid.values);
  EXPECT_TRUE(mc.extract(values, grid, kSurface).triangles.empty());
}

}  // namespace

namespace {

// The chunk on a device's limits: the group counts NVIDIA reports (2^31 - 1 along x) once made the
// chunk (2^31 - 1) * 256, truncated to 32 bits (a 16 GiB flags buffer, and blocksFor(chunk + 1)
// wrapping). Whatever the limits, the chunk's dispatches fit them, its flags fit the storage
// range, and it is never larger than on a device with 65,535 groups.
VkPhysicalDeviceLimits limitsWithGroups(uint32_t groups, uint32_t storageRange) {
  VkPhysicalDeviceLimits l{};
  l.maxComputeWorkGroupCount[0] = l.maxComputeWorkGroupCount[1] = l.maxComputeWorkGroupCount[2] = 65535;
  l.maxComputeWorkGroupCount[0] = groups;
  l.maxStorageBufferRange = storageRange;
  return l;
}

TEST(MarchingCubesChunk, FitsEveryDevicesLimits) {
  const uint64_t kLocal = 256;  // shaders/mesh/marching_cubes.glsl
  const uint64_t onCommonLimits = nerf::MarchingCubes::chunkFor(limitsWithGroups(65535, 1u << 27), 0);
  EXPECT_EQ(onCommonLimits, (65535 * kLocal - 1) / 1024 * 1024);
  for (uint32_t groups : {65535u, 1u << 20, 2147483647u, 4294967295u})
    for (uint32_t range : {1u << 27, 4294967295u}) {
      const auto l = limitsWithGroups(groups, range);
      const uint64_t chunk = nerf::MarchingCubes::chunkFor(l, 0);
      SCOPED_TRACE(std::to_string(groups) + " groups, storage range " + std::to_string(range));
      EXPECT_GT(chunk, 0u);
      EXPECT_EQ(chunk % 1024, 0u);
      EXPECT_LE(chunk, nerf::MarchingCubes::kMaxChunk);
      EXPECT_LE((chunk + 1 + kLocal - 1) / kLocal, groups);  // the scan of chunk + 1 in one dispatch
      EXPECT_LE(chunk * 4, range);                            // the flags in one binding
      EXPECT_LE(chunk, onCommonLimits + 1024);                // no more memory than at 65,535 groups
    }
  EXPECT_EQ(nerf::MarchingCubes::chunkFor(limitsWithGroups(2147483647u, 4294967295u), 5000), 4096u);
}

}  // namespace

// Cells no training camera sees start and stay empty (OccupancyGrid::markUnseenEmpty,
// shaders/occupancy/occupancy_mark_unseen.comp) against the CPU twin (ref::markUnseenEmpty).
#include <cmath>
#include <vector>

#include "nerf/occupancy/occupancy_grid.h"
#include "reference/occupancy/occupancy_grid.h"
#include "reference/occupancy/view_bounds.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "vknerf/camera.h"

using namespace vknerf;

namespace {

class OccupancyUnseen : public test::GpuTest {};

// Three narrow cameras on one side of the box, one of them behind a lens with strong barrel
// distortion: most of the box, and all that is behind them, is out of view.
std::vector<Camera> sideCameras() {
  std::vector<Camera> cams;
  for (int i = 0; i < 3; ++i) {
    Camera c = pinholeFromFov(64, 48, 30.0f, lookAt({3.0f, 0.4f * float(i - 1), 0.2f}, {0, 0, 0}, {0, 0, 1}));
    if (i == 2) {
      c.lens.model = LensModel::OpenCV;
      c.lens.k1 = -0.2f;
      c.lens.k2 = 0.05f;
      c.lens.p1 = 0.001f;
    }
    cams.push_back(c);
  }
  return cams;
}

TEST_F(OccupancyUnseen, ShaderMatchesReferenceOverCascades) {
  const uint32_t r = 12, cascades = 3;
  Aabb box;
  box.min = {-2.0f, -1.5f, -1.0f};
  box.max = {2.0f, 2.5f, 1.0f};
  const auto cams = sideCameras();
  nerf::OccupancyGrid grid(ctx(), r, cascades);
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) { grid.recordMarkAllOccupied(rec); });
  grid.markUnseenEmpty(cams, box);

  const std::array<float, 3> centre{0.0f, 0.5f, 0.0f}, half{2.0f, 2.0f, 1.0f};
  std::vector<float> density(grid.numCells(), 0.0f);
  ref::markUnseenEmpty(ref::viewBoundsOf(cams), r, cascades, centre, half, density);
  const auto gd = grid.density().download<float>(grid.numCells());
  const auto gb = grid.bits().download<uint32_t>(grid.numWords());
  uint32_t unseen = 0;
  for (uint32_t i = 0; i < grid.numCells(); ++i) {
    ASSERT_EQ(gd[i], density[i]) << "cell " << i;
    ASSERT_EQ(ref::bitSet(gb, i), density[i] >= 0.0f) << "cell " << i;
    unseen += density[i] < 0.0f;
  }
  // Not vacuous: some of every cascade seen, a good share of the cells not.
  EXPECT_GT(unseen, grid.numCells() / 4);
  EXPECT_LT(unseen, grid.numCells());
}

TEST_F(OccupancyUnseen, UnseenCellsStayEmptyThroughUpdates) {
  const uint32_t r = 7;  // 343 cells: the last bit word is partial, its padding cells 0 > -1/2
  Aabb box;
  const auto cams = sideCameras();
  nerf::OccupancyGrid grid(ctx(), r);
  grid.markUnseenEmpty(cams, box);
  const auto before = grid.density().download<float>(grid.numCells());
  // The marking's threshold (-1/2) lies below the padding's 0: no bit past the last cell is set.
  EXPECT_EQ(grid.bits().download<uint32_t>(grid.numWords()).back() >> (grid.numCells() % 32), 0u);
  // Every cell measured dense, many times over: the seen ones turn on, the unseen stay at -1.
  std::vector<uint32_t> cells(grid.numCells());
  for (uint32_t i = 0; i < grid.numCells(); ++i) cells[i] = i;
  gpu::Buffer cellBuf = gpu::Buffer::of(ctx(), cells);
  gpu::Buffer dense = gpu::Buffer::of(ctx(), std::vector<float>(grid.numCells(), 100.0f));
  for (int u = 0; u < 3; ++u)
    test::submitOnce(ctx(), [&](gpu::Recorder& rec) { grid.recordUpdate(rec, {cellBuf, dense, grid.numCells()}, {0.95f, 0.01f}); });
  const auto after = grid.density().download<float>(grid.numCells());
  const auto bits = grid.bits().download<uint32_t>(grid.numWords());
  uint32_t unseen = 0;
  for (uint32_t i = 0; i < grid.numCells(); ++i) {
    if (before[i] < 0.0f) {
      ++unseen;
      EXPECT_EQ(after[i], -1.0f) << "cell " << i;
      EXPECT_FALSE(ref::bitSet(bits, i)) << "cell " << i;
    } else {
      EXPECT_EQ(after[i], 100.0f) << "cell " << i;
      EXPECT_TRUE(ref::bitSet(bits, i)) << "cell " << i;
    }
  }
  EXPECT_GT(unseen, 0u);
}

// The pinhole bound holds every pixel's ray: points along rays through the image's edge pixels
// (through the lens) are seen, points just outside a pinhole image are not.
TEST(ViewBounds, HoldEveryPixelsRay) {
  for (const Camera& c : sideCameras()) {
    const ref::ViewBound b = ref::viewBoundOf(c);
    for (float u : {0.5f, 16.0f, 32.0f, 63.5f})
      for (float v : {0.5f, 24.0f, 47.5f}) {
        const auto d = ref::lensDirection(c.lens, double(u - c.cx) / c.fx, double(v - c.cy) / c.fy);
        // OpenCV camera frame (x right, y down, z forward) -> OpenGL camera frame -> world.
        const double g[3] = {d[0], -d[1], -d[2]};
        std::array<float, 3> p;
        for (int k = 0; k < 3; ++k)
          p[k] = float(c.c2w[k * 4 + 3] + 2.0 * (c.c2w[k * 4] * g[0] + c.c2w[k * 4 + 1] * g[1] + c.c2w[k * 4 + 2] * g[2]));
        EXPECT_TRUE(ref::pointSeen(b, p)) << "pixel " << u << "," << v;
      }
    if (c.lens.model == LensModel::Pinhole) {
      EXPECT_LT(b.xMax, 1.05f * (float(c.width) - c.cx) / c.fx);
      EXPECT_GT(b.xMax, (float(c.width) - c.cx) / c.fx);
    }
    EXPECT_FALSE(ref::pointSeen(b, {c.c2w[3] + 1.0f, c.c2w[7], c.c2w[11]}));  // behind: the cameras look towards -x
  }
}

}  // namespace

// rays.comp against the CPU reference (tests/reference/rays/rays.h).
#include <algorithm>
#include <cmath>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "nerf/rays/rays.h"
#include "reference/rays/camera_runs.h"
#include "reference/rays/rays.h"
#include "reference/rng.h"

using namespace vknerf;

namespace {

// A camera at `eye` looking at the origin, +Z up, as nerf_synthetic poses are.
Camera originCamera(std::array<float, 3> eye, uint32_t w, uint32_t h, float focal) {
  return pinholeFromFocal(w, h, focal, lookAt(eye, {0, 0, 0}, {0, 0, 1}));
}

struct GpuRays {
  std::vector<float> rays;         // 8 floats per ray
  std::vector<uint32_t> pixelIds;  // 2 per ray
};

GpuRays runRays(Context& ctx, const std::vector<Camera>& cams, bool random, uint32_t cam, uint32_t first,
                uint32_t count, const Aabb& box, float nearPlane, uint32_t seed = 0, bool inCameraRuns = false) {
  auto packed = nerf::packCameras(cams);
  auto camBuf = gpu::Buffer::of(ctx, packed);
  gpu::Buffer rays(ctx, count * nerf::kRayBytes), ids(ctx, count * nerf::kPixelIdBytes);
  nerf::RayGeneration gen(ctx);
  test::submitOnce(ctx, [&](gpu::Recorder& rec) {
    if (random)
      gen.recordRandom(rec, camBuf, {uint32_t(cams.size()), seed, count, inCameraRuns}, {box, nearPlane}, {rays, ids});
    else
      gen.recordImage(rec, camBuf, {cam, first, count}, {box, nearPlane}, {rays, ids});
  });
  return {rays.download<float>(count * 8), ids.download<uint32_t>(count * 2)};
}

// Directions are normalised products of O(1) values: float rounding of a few ops gives ~1e-6
// relative error; t values are ratios of box distances and direction components, conditioned
// like 1/|d_k|, hence the looser absolute bound on t.
constexpr double kDirTol = 2e-6, kTRel = 1e-5, kTAbs = 1e-5;

void expectRayMatches(const float* g, const ref::Ray<double>& r) {
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(test::near(g[k], r.o[k], kDirTol, kDirTol));
    EXPECT_TRUE(test::near(g[4 + k], r.d[k], kDirTol, kDirTol));
  }
  EXPECT_EQ(g[3] >= 0, r.hit());
  if (r.hit()) {
    EXPECT_TRUE(test::near(g[3], r.tNear, kTRel, kTAbs));
    EXPECT_TRUE(test::near(g[7], r.tFar, kTRel, kTAbs));
  } else {
    EXPECT_EQ(g[3], -1.0f);
    EXPECT_EQ(g[7], -1.0f);
  }
}

// Training ray i drawn with `seed` has camera `cam`, the reference's pixel of it, and its ray.
void expectTrainingRay(const GpuRays& out, const std::vector<Camera>& cams, uint32_t seed, uint32_t i, uint32_t cam) {
  const uint32_t pixel = ref::rngUint(seed, i, 1) % (cams[cam].width * cams[cam].height);
  ASSERT_EQ(out.pixelIds[2 * i], cam) << "ray " << i;
  ASSERT_EQ(out.pixelIds[2 * i + 1], pixel) << "ray " << i;
  auto r = ref::cameraRay<double>(cams[cam], pixel % cams[cam].width, pixel / cams[cam].width);
  ref::intersectAabb(r, Aabb{}, 0.0);
  expectRayMatches(&out.rays[8 * i], r);
}

class Rays : public test::GpuTest {};

}  // namespace

TEST_F(Rays, WholeImageMatchesReference) {
  Aabb box{{-1.5f, -1.5f, -1.5f}, {1.5f, 1.5f, 1.5f}};
  std::vector<Camera> cams = {originCamera({4, 0.5f, 1}, 37, 23, 40), originCamera({-1, 3, 2.5f}, 16, 16, 20)};
  for (uint32_t ci = 0; ci < cams.size(); ++ci) {
    const Camera& c = cams[ci];
    uint32_t n = c.width * c.height;
    auto out = runRays(ctx(), cams, false, ci, 0, n, box, 0.05f);
    for (uint32_t p = 0; p < n; ++p) {
      auto r = ref::cameraRay<double>(c, p % c.width, p / c.width);
      ref::intersectAabb(r, box, 0.05);
      expectRayMatches(&out.rays[8 * p], r);
      EXPECT_EQ(out.pixelIds[2 * p], ci);
      EXPECT_EQ(out.pixelIds[2 * p + 1], p);
    }
  }
}

TEST_F(Rays, PixelCentresAndOpenGlConvention) {
  // Identity pose, principal point at the centre: the centre pixel of an odd-sized image looks
  // straight down -Z; the top-left pixel's ray points to -X (left) and +Y (up).
  Camera c;
  c.fx = c.fy = 10;
  c.width = c.height = 5;
  c.cx = c.cy = 2.5f;
  c.c2w[11] = 5;  // camera at z = 5
  auto centre = ref::cameraRay<double>(c, 2, 2);
  EXPECT_NEAR(centre.d[0], 0, 1e-12);
  EXPECT_NEAR(centre.d[1], 0, 1e-12);
  EXPECT_NEAR(centre.d[2], -1, 1e-12);
  auto corner = ref::cameraRay<double>(c, 0, 0);
  EXPECT_LT(corner.d[0], 0);
  EXPECT_GT(corner.d[1], 0);
  auto out = runRays(ctx(), {c}, false, 0, 12, 1, Aabb{}, 0);
  EXPECT_TRUE(test::near(out.rays[4 + 2], -1.0, 1e-6, 1e-6));
  EXPECT_TRUE(test::near(out.rays[3], 4.0, 1e-6, 1e-6));  // enters the unit box at z = 1
  EXPECT_TRUE(test::near(out.rays[7], 6.0, 1e-6, 1e-6));  // leaves at z = -1
}

TEST_F(Rays, DirectionComponentExactlyZero) {
  // Identity rotation: the centre pixel's direction is exactly (0, 0, -1), parallel to four faces.
  Camera c;
  c.fx = c.fy = 10;
  c.width = c.height = 1;
  c.cx = c.cy = 0.5f;
  c.c2w[11] = 3;
  auto inside = runRays(ctx(), {c}, false, 0, 0, 1, Aabb{}, 0);
  EXPECT_EQ(inside.rays[4], 0.0f);
  EXPECT_EQ(inside.rays[5], 0.0f);
  EXPECT_TRUE(test::near(inside.rays[3], 2.0, 1e-6, 1e-6));
  EXPECT_TRUE(test::near(inside.rays[7], 4.0, 1e-6, 1e-6));
  // The same ray shifted outside the x-slab misses, with no NaN from 0 * inf.
  c.c2w[3] = 1.5f;
  auto outside = runRays(ctx(), {c}, false, 0, 0, 1, Aabb{}, 0);
  EXPECT_EQ(outside.rays[3], -1.0f);
  EXPECT_EQ(outside.rays[7], -1.0f);
  // Exactly on the face x = 1: inside the closed slab, a hit.
  c.c2w[3] = 1.0f;
  auto onFace = runRays(ctx(), {c}, false, 0, 0, 1, Aabb{}, 0);
  EXPECT_TRUE(test::near(onFace.rays[3], 2.0, 1e-6, 1e-6));
}

TEST_F(Rays, OriginInsideBoxStartsAtNearPlane) {
  Camera c = originCamera({0.2f, 0.1f, 0.3f}, 8, 8, 6);
  Aabb box;
  auto out = runRays(ctx(), {c}, false, 0, 0, 64, box, 0.01f);
  for (uint32_t p = 0; p < 64; ++p) {
    EXPECT_FLOAT_EQ(out.rays[8 * p + 3], 0.01f);
    EXPECT_GT(out.rays[8 * p + 7], 0.01f);
    auto r = ref::cameraRay<double>(c, p % 8, p / 8);
    ref::intersectAabb(r, box, 0.01);
    expectRayMatches(&out.rays[8 * p], r);
  }
}

TEST_F(Rays, CameraLookingAwayMissesBox) {
  Camera c = originCamera({5, 0, 0}, 4, 4, 4);
  for (int k = 0; k < 3; ++k) c.c2w[4 * k + 2] = -c.c2w[4 * k + 2];  // flip the viewing axis
  for (int k = 0; k < 3; ++k) c.c2w[4 * k] = -c.c2w[4 * k];          // keep the frame right-handed
  auto out = runRays(ctx(), {c}, false, 0, 0, 16, Aabb{}, 0);
  for (uint32_t p = 0; p < 16; ++p) {
    EXPECT_EQ(out.rays[8 * p + 3], -1.0f);
    EXPECT_EQ(out.rays[8 * p + 7], -1.0f);
  }
}

TEST_F(Rays, RandomPixelsMatchCounterRng) {
  std::vector<Camera> cams = {originCamera({4, 0, 1}, 10, 7, 9), originCamera({0, 4, 1}, 5, 12, 9),
                              originCamera({-3, -3, 2}, 9, 9, 9)};
  const uint32_t n = 1000, seed = 1234;
  auto out = runRays(ctx(), cams, true, 0, seed, n, Aabb{}, 0, seed);
  std::vector<int> perCamera(cams.size());
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t cam = ref::rngUint(seed, i, 0) % cams.size();
    ASSERT_NO_FATAL_FAILURE(expectTrainingRay(out, cams, seed, i, cam));
    perCamera[cam]++;
  }
  for (int c : perCamera) EXPECT_GT(c, 250);  // roughly uniform over cameras (expected 333)
}

// Training batches in runs of one camera each (camera_runs.glsl): each ray's camera and pixel as
// the reference draws them, the cameras in consecutive runs whose lengths differ by at most one,
// every camera with its run when there are more rays than cameras, and distinct cameras, one ray
// each, when there are fewer.
TEST_F(Rays, PixelsInCameraRunsMatchTheReference) {
  std::vector<Camera> cams = {originCamera({4, 0, 1}, 10, 7, 9), originCamera({0, 4, 1}, 5, 12, 9),
                              originCamera({-3, -3, 2}, 9, 9, 9), originCamera({3, 3, 2}, 6, 6, 9),
                              originCamera({-4, 0, 1}, 8, 5, 9)};
  const uint32_t C = cams.size();
  for (const uint32_t n : {1000u, 3u})
    for (const uint32_t seed : {1234u, 99u}) {
      SCOPED_TRACE(testing::Message() << n << " rays, seed " << seed);
      auto out = runRays(ctx(), cams, true, 0, seed, n, Aabb{}, 0, seed, true);
      std::vector<uint32_t> perCamera(C);
      uint32_t changes = 0;
      for (uint32_t i = 0; i < n; ++i) {
        const uint32_t cam = ref::groupedCamera(seed, i, n, C);
        ASSERT_NO_FATAL_FAILURE(expectTrainingRay(out, cams, seed, i, cam));
        perCamera[cam]++;
        changes += i > 0 && out.pixelIds[2 * i] != out.pixelIds[2 * i - 2];
      }
      EXPECT_EQ(changes, std::min(n, C) - 1);  // each camera's rays are one run
      for (uint32_t c : perCamera)
        if (n >= C) EXPECT_TRUE(c == n / C || c == n / C + 1) << c;
        else EXPECT_LE(c, 1u);
    }
}

// The runs cut [0, N) into C consecutive pieces, run k's rays being the rays whose run is k.
TEST(CameraRuns, RunsPartitionTheBatch) {
  for (const uint32_t N : {1u, 7u, 64u, 1000u, 4096u})
    for (const uint32_t C : {1u, 3u, 7u, 64u, 100u, 5000u}) {
      uint32_t next = 0;
      for (uint32_t k = 0; k < C; ++k) {
        const auto [first, end] = ref::cameraRunRays(k, N, C);
        ASSERT_EQ(first, next) << N << " rays, " << C << " cameras, run " << k;
        ASSERT_LE(end - first, N / C + 1);
        for (uint32_t i = first; i < end; ++i) ASSERT_EQ(ref::cameraRunOfRay(i, N, C), k) << i;
        next = end;
      }
      ASSERT_EQ(next, N);
    }
}

TEST_F(Rays, EmptyBatchDispatchesNothing) {
  auto out = runRays(ctx(), {originCamera({3, 0, 0}, 4, 4, 4)}, false, 0, 0, 0, Aabb{}, 0);
  EXPECT_TRUE(out.rays.empty());
}

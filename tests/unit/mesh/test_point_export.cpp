// Point-cloud export: a rendered view's opaque pixels placed on an analytic surface, the PLY read
// back, a tiny model's render turned into points, and `vknerf export points` with its usage errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "reference/rays/rays.h"
#include "support/cli_run.h"
#include "support/gpu_test.h"
#include "support/ply_reader.h"
#include "support/temp_dir.h"
#include "support/tiny_config.h"
#include "vknerf/error.h"
#include "vknerf/point_cloud.h"
#include "vknerf/trainer.h"

using namespace vknerf;

namespace {

constexpr float kRadius = 0.8f;
constexpr std::array<float, 3> kWhite{1, 1, 1};

// What a render of the ball |x| < kRadius would give, exactly: the depth of the ray's first hit,
// opacity 1 there (0.4 on every third hit pixel, to be thresholded away) and 0 on misses; a colour
// that names the pixel.
RenderedImage ballView(const Camera& cam) {
  RenderedImage img;
  img.width = cam.width;
  img.height = cam.height;
  for (uint32_t y = 0; y < cam.height; ++y)
    for (uint32_t x = 0; x < cam.width; ++x) {
      const auto r = ref::cameraRay<double>(cam, x, y);
      double b = 0, c = -double(kRadius) * kRadius;
      for (int k = 0; k < 3; ++k) b += r.o[k] * r.d[k], c += r.o[k] * r.o[k];
      const double disc = b * b - c;
      const size_t i = size_t(y) * cam.width + x;
      const bool hit = disc > 0;
      img.depth.push_back(hit ? float(-b - std::sqrt(disc)) : 0.0f);
      img.opacity.push_back(hit ? (i % 3 == 0 ? 0.4f : 1.0f) : 0.0f);
      for (float v : {float(x) / cam.width, float(y) / cam.height, 0.25f}) img.rgb.push_back(v);
    }
  return img;
}

size_t countAbove(const RenderedImage& img, float threshold) {
  size_t n = 0;
  for (float a : img.opacity) n += a > threshold;
  return n;
}

void expectOnTheBall(const PointCloud& cloud, float tolerance) {
  for (size_t p = 0; p < cloud.positions.size(); p += 3) {
    const float* x = &cloud.positions[p];
    ASSERT_NEAR(std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), kRadius, tolerance) << "point " << p / 3;
  }
}

TEST(VisiblePoints, LieOnTheSurfaceTheViewSees) {
  Camera cam = pinholeFromFov(40, 30, 50, lookAt({0.5f, -2.5f, 1.2f}, {0, 0, 0}, {0, 0, 1}));
  const RenderedImage img = ballView(cam);
  PointCloud cloud;
  appendVisiblePoints(cloud, cam, img, 0.5f, kWhite);
  ASSERT_EQ(cloud.positions.size() / 3, countAbove(img, 0.5f));
  ASSERT_GT(cloud.positions.size(), 300u);
  EXPECT_EQ(cloud.colors.size(), cloud.positions.size());
  expectOnTheBall(cloud, 1e-5f);
  // A second view appends; a lower threshold keeps the faint pixels too.
  cam.c2w = lookAt({-2.0f, 1.0f, -1.0f}, {0, 0, 0}, {0, 0, 1});
  const RenderedImage other = ballView(cam);
  const size_t first = cloud.positions.size() / 3;
  appendVisiblePoints(cloud, cam, other, 0.3f, kWhite);
  EXPECT_EQ(cloud.positions.size() / 3 - first, countAbove(other, 0.3f));
  expectOnTheBall(cloud, 1e-5f);
}

TEST(VisiblePoints, FollowTheLensRays) {
  Camera cam = pinholeFromFov(32, 32, 60, lookAt({0, -2.2f, 0.3f}, {0, 0, 0}, {0, 0, 1}));
  cam.lens.model = LensModel::OpenCV;
  cam.lens.k1 = -0.2f;
  cam.lens.p1 = 0.01f;
  PointCloud cloud;
  appendVisiblePoints(cloud, cam, ballView(cam), 0.5f, kWhite);
  ASSERT_GT(cloud.positions.size(), 0u);
  expectOnTheBall(cloud, 1e-5f);
}

// A pixel 60% opaque over a background: the point carries the field's colour, not the blend.
TEST(VisiblePoints, TakeTheBackgroundBackOut) {
  const Camera cam = pinholeFromFov(1, 1, 50);
  const std::array<float, 3> field{0.2f, 0.6f, 1.0f}, background{1.0f, 0.5f, 0.0f};
  RenderedImage img{1, 1, {}, {2.0f}, {0.6f}};
  for (int k = 0; k < 3; ++k) img.rgb.push_back(0.6f * field[k] + 0.4f * background[k]);
  PointCloud cloud;
  appendVisiblePoints(cloud, cam, img, 0.5f, background);
  ASSERT_EQ(cloud.colors.size(), 3u);
  // unitToByte rounds to the nearest of 255 steps: within one step of the field's colour.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(cloud.colors[k], field[k] * 255.0f, 1.0f) << "channel " << k;
}

// A render's own background per pixel (a learned far field) wins over the constant one given.
TEST(VisiblePoints, TakeTheImagesOwnBackgroundBackOut) {
  const Camera cam = pinholeFromFov(2, 1, 50);
  const std::array<float, 3> field{0.2f, 0.6f, 1.0f};
  const float behind[2][3] = {{1.0f, 0.5f, 0.0f}, {0.1f, 0.9f, 0.3f}};
  RenderedImage img{2, 1, {}, {2.0f, 2.0f}, {0.6f, 0.7f}, {}};
  for (int p = 0; p < 2; ++p)
    for (int k = 0; k < 3; ++k) {
      img.rgb.push_back(img.opacity[p] * field[k] + (1 - img.opacity[p]) * behind[p][k]);
      img.background.push_back(behind[p][k]);
    }
  PointCloud cloud;
  appendVisiblePoints(cloud, cam, img, 0.5f, kWhite);
  ASSERT_EQ(cloud.colors.size(), 6u);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(cloud.colors[k], field[k % 3] * 255.0f, 1.0f) << "value " << k;
  img.background.pop_back();
  EXPECT_THROW(appendVisiblePoints(cloud, cam, img, 0.5f, kWhite), Error);
}

TEST(VisiblePoints, RejectAnImageOfAnotherSize) {
  Camera cam = pinholeFromFov(8, 8, 50);
  RenderedImage img = ballView(pinholeFromFov(8, 6, 50));
  PointCloud cloud;
  EXPECT_THROW(appendVisiblePoints(cloud, cam, img, 0.5f, kWhite), Error);
}

TEST(Ply, RoundTripsAPointCloud) {
  PointCloud cloud;
  for (int i = 0; i < 50; ++i) {
    for (float v : {0.1f * i, -0.5f * i, 1e-3f * i * i}) cloud.positions.push_back(v);
    for (int k = 0; k < 3; ++k) cloud.colors.push_back(uint8_t(i * 37 + k));
  }
  test::TempDir dir("ply");
  writePly(dir.file("points.ply"), cloud);
  Mesh back = test::readPly(dir.file("points.ply"), false);
  EXPECT_EQ(back.positions, cloud.positions);
  EXPECT_EQ(back.colors, cloud.colors);
  EXPECT_TRUE(back.triangles.empty());
  EXPECT_THROW(writePly(dir.file("bad.ply"), PointCloud{{0, 0, 0}, {1, 2}}), Error);
}

class PointExport : public test::GpuTest {};

// A model's own render: as many points as pixels above the threshold, each at its pixel's depth
// from the camera's centre.
TEST_F(PointExport, TinyModelGivesAPointPerOpaquePixel) {
  Dataset data = Dataset::load(test::scene(), {.downscale = 10});
  Trainer trainer(test::sharedContext(), data, test::tinyVanillaConfig());
  for (int i = 0; i < 2; ++i) trainer.step();
  const Camera& cam = data.cameras[0];
  const RenderedImage img = trainer.model().render(cam);
  std::vector<float> sorted = img.opacity;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const float threshold = sorted[sorted.size() / 2];  // about half the pixels, whatever the field
  PointCloud cloud;
  appendVisiblePoints(cloud, cam, img, threshold, trainer.model().config().background);
  ASSERT_EQ(cloud.positions.size() / 3, countAbove(img, threshold));
  size_t p = 0;
  for (size_t i = 0; i < img.opacity.size(); ++i) {
    if (!(img.opacity[i] > threshold)) continue;
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += std::pow(cloud.positions[3 * p + k] - cam.c2w[4 * k + 3], 2);
    EXPECT_NEAR(std::sqrt(d2), img.depth[i], 1e-4 * (1 + img.depth[i])) << "pixel " << i;
    ++p;
  }
}

TEST(PointExportCli, WritesAPlyAndRejectsBadFlags) {
  using test::runCli;
  const std::string model = test::temp("points.vknerf"), ply = test::temp("points.ply");
  ASSERT_EQ(runCli("train " + test::scene() + " --steps 2 --downscale 10 -o " + model).code, 0);
  const std::string base = "export points " + model + " --scene " + test::scene() + " --downscale 20 -o " + ply;
  auto r = runCli(base + " --min-opacity 0");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("view 1/"), std::string::npos) << r.output;
  const Mesh all = test::readPly(ply, false);
  EXPECT_NE(r.output.find(std::to_string(all.positions.size() / 3) + " points written"), std::string::npos) << r.output;
  ASSERT_GT(all.positions.size(), 21u);
  r = runCli(base + " --min-opacity 0 --max-points 7");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(test::readPly(ply, false).positions.size(), 21u);
  EXPECT_NE(r.output.find("evenly kept of"), std::string::npos) << r.output;
  EXPECT_EQ(runCli("export points " + model + " -o " + ply).code, 2);  // no --scene
  EXPECT_EQ(runCli(base + " --min-opacity 1.5").code, 2);
  EXPECT_EQ(runCli(base + " --downscale 0").code, 2);
  EXPECT_EQ(runCli("export points /no/such.vknerf --scene " + test::scene() + " -o " + ply).code, 1);
}

}  // namespace

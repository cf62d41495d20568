// COLMAP text models: pose conversion (OpenCV world-to-camera quaternions -> OpenGL camera-to-world),
// camera models, scene normalisation, folder layouts and malformed input.
#include <cmath>
#include <cstdio>

#include "reference/rays/rays.h"
#include "support/colmap_model_files.h"
#include "support/dataset_files.h"
#include "support/error_message.h"
#include "support/temp_dir.h"

using namespace vknerf;
using namespace vknerf::test;

namespace {

std::string imageLine(int id, const W2c& p, int camera, const std::string& name) {
  auto q = quaternion(p.R);
  char buf[512];
  std::snprintf(buf, sizeof buf, "%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %d %s\n", id, q[0], q[1], q[2], q[3],
                p.t[0], p.t[1], p.t[2], camera, name.c_str());
  return buf;
}

class DatasetColmap : public TempDirTest {
 protected:
  // A model in `model` and images (w x h) for `names` in `scene`/images.
  void writeModel(const fs::path& model, const std::string& cameras, const std::string& images,
                  const std::vector<std::string>& names, const fs::path& scene, uint32_t w = 16, uint32_t h = 12) {
    writeText(model / "cameras.txt", "# Camera list with one line of data per camera:\n" + cameras);
    writeText(model / "images.txt", "# Image list with two lines of data per image:\n" + images);
    fs::create_directories(scene / "images");
    for (size_t i = 0; i < names.size(); ++i) writePng(scene / "images" / names[i], patternImage(w, h, uint32_t(i)));
  }
  void writeModel(const std::string& cameras, const std::string& images, const std::vector<std::string>& names) {
    writeModel(dir() / "sparse" / "0", cameras, images, names, dir());
  }
  std::string loadError() {
    return errorOf([&] { Dataset::load(dir().string(), {.split = "all"}); });
  }
};

const std::string kPinhole = "1 PINHOLE 16 12 20 20 8 6\n";

}  // namespace

TEST_F(DatasetColmap, PoseRoundTripAndPointsNormalisation) {
  const Vec3 target{2, 1, 2};
  const std::vector<Vec3> eyes = {{8, 1, 3}, {-4, 0, 2.5}, {2, 7, 1}, {1, -5, 4}, {3, 2, -4}, {2.1, 0.9, 9}};
  std::string images;
  std::vector<std::string> names;
  std::vector<std::array<double, 16>> poses;
  for (size_t i = 0; i < eyes.size(); ++i) {
    poses.push_back(poseLookingAt(eyes[i], target));
    names.push_back("img" + std::to_string(i) + ".png");
    images += imageLine(int(i) + 1, fromOpenGl(poses.back()), 1, names.back()) + "\n";
  }
  writeModel(kPinhole, images, names);
  // 11^3 grid points over x in [-2, 6], y in [0, 2], z in [1, 3]: each axis's 1st and 99th
  // percentiles are its grid ends (each end value is 1/11 of the points), the 5% pad is 0.05 * 8,
  // so the box centre is (2, 1, 2) and its largest half extent 4.4 becomes 1.
  std::string pts = "# 3D point list\n";
  int id = 1;
  for (int a = 0; a <= 10; ++a)
    for (int b = 0; b <= 10; ++b)
      for (int c = 0; c <= 10; ++c)
        pts += std::to_string(id++) + " " + std::to_string(-2 + 0.8 * a) + " " + std::to_string(0.2 * b) + " " +
               std::to_string(1 + 0.2 * c) + " 128 128 128 0.5 1 0 2 3\n";
  writeText(dir() / "sparse" / "0" / "points3D.txt", pts);

  Dataset d = Dataset::load(dir().string(), {.split = "all"});
  ASSERT_EQ(d.cameras.size(), eyes.size());
  EXPECT_EQ(d.boundsSource, "points3D");
  const double s = 1 / 4.4;
  const double half[3] = {1, 1.4 * s, 1.4 * s};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(d.bounds.min[k], -half[k], 1e-6);
    EXPECT_NEAR(d.bounds.max[k], half[k], 1e-6);
  }
  for (size_t i = 0; i < eyes.size(); ++i) {
    const Camera& c = d.cameras[i];
    EXPECT_EQ(fs::path(d.names[i]).filename(), names[i]);
    // Rotations go through a %.17g quaternion and one float rounding: ~1e-7.
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(c.c2w[4 * r + k], poses[i][4 * r + k], 1e-6) << "camera " << i;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c.c2w[4 * k + 3], s * (eyes[i][k] - target[k]), 1e-6);
    EXPECT_EQ(c.fx, 20.0f);
    EXPECT_EQ(c.cx, 8.0f);
  }
}

// A room around the points box: 1331 grid points as above, plus 10 sparse "wall" points (0.75% of
// them: the 99th percentile stays on the grid) whose largest offset from the box centre is 2.5 half extents and one stray point at 1000:
// the box holds 99.9% of the points once scaled by 4 (the power of two above 2.5; the stray point is
// past the 99.9th percentile), so the scene box is the points box times 4, with aabbScale 4.
TEST_F(DatasetColmap, PointsBeyondThePointsBoxWidenItIntoCascades) {
  const Vec3 target{2, 1, 2};
  const std::vector<Vec3> eyes = {{8, 1, 3}, {-4, 0, 2.5}, {2, 7, 1}};
  std::string images;
  std::vector<std::string> names;
  for (size_t i = 0; i < eyes.size(); ++i) {
    names.push_back("img" + std::to_string(i) + ".png");
    images += imageLine(int(i) + 1, fromOpenGl(poseLookingAt(eyes[i], target)), 1, names.back()) + "\n";
  }
  writeModel(kPinhole, images, names);
  std::string pts = "# 3D point list\n";
  int id = 1;
  auto point = [&](double x, double y, double z) {
    pts += std::to_string(id++) + " " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(z) + " 128 128 128 0.5 1 0 2 3\n";
  };
  for (int a = 0; a <= 10; ++a)
    for (int b = 0; b <= 10; ++b)
      for (int c = 0; c <= 10; ++c) point(-2 + 0.8 * a, 0.2 * b, 1 + 0.2 * c);
  for (int i = 0; i < 10; ++i) point(2 + 2.5 * 4.4, 0.1 * i, 2);  // the wall: x offset 2.5 * 4.4
  point(1000, 1, 2);
  writeText(dir() / "sparse" / "0" / "points3D.txt", pts);

  Dataset d = Dataset::load(dir().string(), {.split = "all"});
  EXPECT_EQ(d.boundsSource, "points3D");
  EXPECT_EQ(d.aabbScale, 4.0f);
  // The points box is the one above, times 4.
  const double s = 1 / 4.4, half[3] = {1, 1.4 * s, 1.4 * s};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(d.bounds.min[k], -4 * half[k], 1e-5);
    EXPECT_NEAR(d.bounds.max[k], 4 * half[k], 1e-5);
  }
  // The cameras are normalised by the points box alone, as without the wall.
  for (size_t i = 0; i < eyes.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(d.cameras[i].c2w[4 * k + 3], s * (eyes[i][k] - target[k]), 1e-6);
}

TEST_F(DatasetColmap, OpenCvCameraLookingDownPlusZBecomesOpenGl) {
  // Camera 1: identity world-to-camera, so it looks along world +z with image rows going down
  // world +y. Camera 2: q = (cos 45, 0, sin 45, 0), turned 90 degrees about y so that it looks
  // along world -x (the last row of R), and moved.
  const Mat3 identity{1, 0, 0, 0, 1, 0, 0, 0, 1}, turned{0, 0, 1, 0, 1, 0, -1, 0, 0};
  const Vec3 t2{0.5, -0.2, 1};
  const double h = std::sqrt(0.5);
  writeModel(kPinhole,
             "1 1 0 0 0 0 0 0 1 a.png\n\n"
             "2 " + std::to_string(h) + " 0 " + std::to_string(h) + " 0 0.5 -0.2 1 1 b.png\n1.5 2.5 -1\n",
             {"a.png", "b.png"});
  Dataset d = Dataset::load(dir().string(), {.split = "all"});
  ASSERT_EQ(d.cameras.size(), 2u);
  const Camera& a = d.cameras[0];
  // OpenGL: the camera looks down its -Z column, so that column is world -z; +Y (up) is world -y.
  const float expected[9] = {1, 0, 0, 0, -1, 0, 0, 0, -1};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.c2w[4 * r + k], expected[3 * r + k], 1e-7);
  auto centre = ref::cameraRay<double>(a, 7, 5);  // pixel centre (7.5, 5.5): (-0.5, -0.5) from (cx, cy)
  EXPECT_GT(centre.d[2], 0.99);

  // Projection in COLMAP's own terms: X = R P + t, u = fx X / Z + cx, v = fy Y / Z + cy. A world
  // point put on pixel centre (x + 0.5, y + 0.5) must lie on vknerf's ray through pixel (x, y),
  // whatever translation and scale normalised the scene.
  const Mat3 Rs[2] = {identity, turned};
  const Vec3 ts[2] = {{0, 0, 0}, t2};
  for (int i = 0; i < 2; ++i) {
    const Vec3 C = mul(transpose(Rs[i]), {-ts[i][0], -ts[i][1], -ts[i][2]});
    for (uint32_t y : {0u, 3u, 11u})
      for (uint32_t x : {0u, 9u, 15u}) {
        const double Z = 2.5;
        Vec3 X{(x + 0.5 - 8) * Z / 20, (y + 0.5 - 6) * Z / 20, Z};
        Vec3 rel = mul(transpose(Rs[i]), {X[0] - ts[i][0], X[1] - ts[i][1], X[2] - ts[i][2]});
        Vec3 P{rel[0], rel[1], rel[2]};
        Vec3 dir{P[0] - C[0], P[1] - C[1], P[2] - C[2]};
        double n = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        auto ray = ref::cameraRay<double>(d.cameras[i], x, y);
        // Float poses and intrinsics: directions agree to ~1e-7.
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(ray.d[k], dir[k] / n, 1e-6) << "camera " << i << " pixel " << x << "," << y;
      }
  }
}

TEST_F(DatasetColmap, PinholeModelsAndZeroDistortion) {
  writeModel(
      "1 SIMPLE_PINHOLE 16 12 20 8 6\n"
      "2 PINHOLE 16 12 21 22 7.5 6.5\n"
      "3 SIMPLE_RADIAL 16 12 23 8.25 6 0\n"
      "4 RADIAL 16 12 24 8 5.75 0 0\n"
      "5 OPENCV 16 12 25 26 8 6 0 0 0 0\n",
      imageLine(1, fromOpenGl(poseLookingAt({4, 0, 0}, {0, 0, 0})), 1, "a.png") + "\n" +
          imageLine(2, fromOpenGl(poseLookingAt({0, 4, 0}, {0, 0, 0})), 2, "b.png") + "\n" +
          imageLine(3, fromOpenGl(poseLookingAt({-4, 0, 1}, {0, 0, 0})), 3, "c.png") + "\n" +
          imageLine(4, fromOpenGl(poseLookingAt({0, -4, 1}, {0, 0, 0})), 4, "d.png") + "\n" +
          imageLine(5, fromOpenGl(poseLookingAt({0, 0, 4}, {0, 0, 0})), 5, "e.png") + "\n",
      {"a.png", "b.png", "c.png", "d.png", "e.png"});
  Dataset d = Dataset::load(dir().string(), {.split = "all"});
  ASSERT_EQ(d.cameras.size(), 5u);
  const float want[5][4] = {{20, 20, 8, 6}, {21, 22, 7.5, 6.5}, {23, 23, 8.25, 6}, {24, 24, 8, 5.75}, {25, 26, 8, 6}};
  for (int i = 0; i < 5; ++i) {
    const Camera& c = d.cameras[i];
    EXPECT_EQ(c.fx, want[i][0]) << i;
    EXPECT_EQ(c.fy, want[i][1]) << i;
    EXPECT_EQ(c.cx, want[i][2]) << i;
    EXPECT_EQ(c.cy, want[i][3]) << i;
    EXPECT_EQ(c.width, 16u);
  }
  // No points3D.txt: the camera box (a cube) normalised to [-1, 1]^3.
  EXPECT_EQ(d.boundsSource, "cameras");
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(d.bounds.min[k], -1, 1e-6);
    EXPECT_NEAR(d.bounds.max[k], 1, 1e-6);
  }
}

TEST_F(DatasetColmap, FolderLayouts) {
  const std::string images = imageLine(1, fromOpenGl(poseLookingAt({4, 0, 0}, {0, 0, 0})), 1, "a.png") + "\n" +
                             imageLine(2, fromOpenGl(poseLookingAt({0, 4, 0}, {0, 0, 0})), 1, "b.png") + "\n";
  struct Layout {
    fs::path model, load;
  };
  const fs::path s = dir() / "scene";
  for (const Layout& l : {Layout{s / "sparse" / "0", s}, Layout{s / "sparse", s}, Layout{s, s},
                          Layout{s / "sparse" / "0", s / "sparse" / "0"}}) {
    fs::remove_all(s);
    writeModel(l.model, kPinhole, images, {"a.png", "b.png"}, s);
    Dataset d = Dataset::load(l.load.string(), {.split = "all"});
    ASSERT_EQ(d.cameras.size(), 2u) << l.model;
    EXPECT_EQ(fs::path(d.names[1]), s / "images" / "b.png");
  }
  fs::remove_all(s / "images");
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::load(s.string()); }), "no images/ folder");
}

TEST_F(DatasetColmap, ImagesSortedByNameThenHeldOut) {
  std::string images;
  int id = 1;
  for (const char* n : {"c.png", "a.png", "b.png"}) {
    images += imageLine(id, fromOpenGl(poseLookingAt({4.0 * id, 0, 1}, {0, 0, 0})), 1, n) + "\n";
    ++id;  // not in the call: reading id there too would be unsequenced
  }
  writeModel(kPinhole, images, {"a.png", "b.png", "c.png"});
  auto names = [&](DatasetOptions o) {
    std::string out;
    for (auto& n : Dataset::load(dir().string(), o).names) out += fs::path(n).filename().string() + " ";
    return out;
  };
  EXPECT_EQ(names({.split = "all"}), "a.png b.png c.png ");
  // 34% of 3 rounds to one frame, the middle one.
  EXPECT_EQ(names({.split = "test", .holdoutFraction = 0.34f}), "b.png ");
  EXPECT_EQ(names({.split = "train", .holdoutFraction = 0.34f}), "a.png c.png ");
}

TEST_F(DatasetColmap, EveryDistortionModelLoadsItsLens) {
  const std::string image = imageLine(1, fromOpenGl(poseLookingAt({4, 0, 0}, {0, 0, 0})), 2, "a.png") + "\n";
  struct Case {
    std::string camera;  // a cameras.txt line for camera 2
    Lens lens;
    float fy;
  };
  const Case cases[] = {
      {"2 SIMPLE_RADIAL 16 12 20 8 6 -0.2", {LensModel::OpenCV, -0.2f}, 20},
      {"2 RADIAL 16 12 20 8 6 -0.2 0.05", {LensModel::OpenCV, -0.2f, 0.05f}, 20},
      {"2 OPENCV 16 12 20 21 8 6 -0.2 0.05 0.001 -0.002", {LensModel::OpenCV, -0.2f, 0.05f, 0, 0, 0, 0, 0.001f, -0.002f}, 21},
      {"2 FULL_OPENCV 16 12 20 21 8 6 -0.2 0.05 0.001 -0.002 0.01 0.1 0.02 0.003",
       {LensModel::OpenCV, -0.2f, 0.05f, 0.01f, 0.1f, 0.02f, 0.003f, 0.001f, -0.002f}, 21},
      {"2 OPENCV_FISHEYE 16 12 20 21 8 6 0.03 -0.006 0.001 -0.0002", {LensModel::Fisheye, 0.03f, -0.006f, 0.001f, -0.0002f}, 21},
      {"2 SIMPLE_RADIAL_FISHEYE 16 12 20 8 6 0.03", {LensModel::Fisheye, 0.03f}, 20},
      {"2 RADIAL_FISHEYE 16 12 20 8 6 0.03 -0.006", {LensModel::Fisheye, 0.03f, -0.006f}, 20},
      {"2 OPENCV 16 12 20 21 8 6 0 0 0 0", {}, 21},  // zero distortion is a pinhole
  };
  for (const Case& c : cases) {
    writeModel(c.camera + "\n", image, {"a.png"});
    Dataset d = Dataset::load(dir().string(), {.split = "all"});
    ASSERT_EQ(d.cameras.size(), 1u);
    const Lens& l = d.cameras[0].lens;
    EXPECT_EQ(l.model, c.lens.model) << c.camera;
    const float got[] = {l.k1, l.k2, l.k3, l.k4, l.k5, l.k6, l.p1, l.p2};
    const float want[] = {c.lens.k1, c.lens.k2, c.lens.k3, c.lens.k4, c.lens.k5, c.lens.k6, c.lens.p1, c.lens.p2};
    for (int k = 0; k < 8; ++k) EXPECT_EQ(got[k], want[k]) << c.camera << " coefficient " << k;
    EXPECT_EQ(d.cameras[0].fx, 20.0f);
    EXPECT_EQ(d.cameras[0].fy, c.fy);
    EXPECT_EQ(d.cameras[0].cx, 8.0f);
  }
  // Downscaling scales the intrinsics and keeps the dimensionless coefficients.
  writeModel("2 OPENCV 16 12 20 21 8 6 -0.2 0.05 0.001 -0.002\n", image, {"a.png"});
  Dataset half = Dataset::load(dir().string(), {.split = "all", .downscale = 2});
  EXPECT_EQ(half.cameras[0].fx, 10.0f);
  EXPECT_EQ(half.cameras[0].cy, 3.0f);
  EXPECT_EQ(half.cameras[0].lens.k1, -0.2f);
  EXPECT_EQ(half.cameras[0].lens.p2, -0.002f);
}

TEST_F(DatasetColmap, UnhandledModelsAndNonInvertibleLensesNameTheRecord) {
  const std::string image = imageLine(1, fromOpenGl(poseLookingAt({4, 0, 0}, {0, 0, 0})), 2, "a.png") + "\n";
  writeModel(kPinhole + "2 FOV 16 12 20 20 8 6 0.9\n", image, {"a.png"});
  EXPECT_MESSAGE_HAS(loadError(), "cameras.txt:3: camera model FOV of camera 2 is not handled");
  writeModel("2 THIN_PRISM_FISHEYE 16 12 20 20 8 6 0 0 0 0 0 0 0 0\n", image, {"a.png"});
  EXPECT_MESSAGE_HAS(loadError(), "cameras.txt:2: camera model THIN_PRISM_FISHEYE of camera 2 is not handled");
  writeModel("2 SIMPLE_RADIAL 16 12 20 8 6 -10\n", image, {"a.png"});
  EXPECT_MESSAGE_HAS(loadError(), "cameras.txt:2: SIMPLE_RADIAL camera 2: k1 = -10: lens distortion does not invert over the image (fails at pixel (0, 0)");
  writeModel("2 OPENCV 16 12 20 20 8 6 0.1 1e300 0 0\n", image, {"a.png"});
  EXPECT_MESSAGE_HAS(loadError(), "cameras.txt:2: camera parameter");
}

TEST_F(DatasetColmap, MalformedInputNamesFileAndLine) {
  const std::string good = imageLine(1, fromOpenGl(poseLookingAt({4, 0, 0}, {0, 0, 0})), 1, "a.png");
  struct Case {
    std::string cameras, images, points, expected;
  };
  const Case cases[] = {
      {kPinhole, good + "\n" + "2 1 0 0 0 0 0 0 7 b.png\n\n", "", "images.txt:4: image 'b.png' uses camera 7"},
      {kPinhole, "1 1 0 x 0 0 0 0 1 a.png\n\n", "", "images.txt:2: quaternion component is not a finite number: 'x'"},
      {kPinhole, "1 1 0 0 0 0 0 0 1\n\n", "", "images.txt:2: expected IMAGE_ID"},
      {kPinhole, good + "1.0 2.0\n", "", "images.txt:3: expected the POINTS2D line"},
      {kPinhole, "1 0 0 0 0 0 0 0 1 a.png\n\n", "", "images.txt:2: quaternion is not unit length"},
      {"1 PINHOLE 16 12 20 20 8\n", good + "\n", "", "cameras.txt:2: PINHOLE needs 4 parameters, got 3"},
      {"1 PINHOLE 16 12 0 20 8 6\n", good + "\n", "", "cameras.txt:2: focal length must be positive"},
      {"1 PINHOLE 16 12 nan 20 8 6\n", good + "\n", "", "cameras.txt:2: camera parameter is not a finite number"},
      {"one PINHOLE 16 12 20 20 8 6\n", good + "\n", "", "cameras.txt:2: CAMERA_ID is not a whole number"},
      {kPinhole + kPinhole, good + "\n", "", "cameras.txt:3: camera 1 is defined twice"},
      {kPinhole, good + "\n", "1 0.5 0.5\n", "points3D.txt:1: expected POINT3D_ID X Y Z"},
      {kPinhole, good + "\n", "1 0.5 zz 0.5 1 1 1 0.1\n", "points3D.txt:1: point coordinate is not a finite number"},
      {"# nothing\n", good + "\n", "", "defines no cameras"},
  };
  for (const Case& c : cases) {
    fs::remove_all(dir());
    writeModel(c.cameras, c.images, {"a.png", "b.png"});
    if (!c.points.empty()) writeText(dir() / "sparse" / "0" / "points3D.txt", c.points);
    EXPECT_MESSAGE_HAS(loadError(), c.expected);
  }
}

TEST_F(DatasetColmap, ImagesMustExistAndMatchTheirCamera) {
  const std::string image = imageLine(1, fromOpenGl(poseLookingAt({4, 0, 0}, {0, 0, 0})), 1, "a.png") + "\n";
  writeModel(kPinhole, image, {});
  std::string e = loadError();
  EXPECT_MESSAGE_HAS(e, "image not found");
  EXPECT_MESSAGE_HAS(e, (dir() / "images" / "a.png").string());
  writeModel(dir() / "sparse" / "0", kPinhole, image, {"a.png"}, dir(), 8, 6);
  e = loadError();
  EXPECT_MESSAGE_HAS(e, "images.txt:2");
  EXPECT_MESSAGE_HAS(e, "is 8x6 but the camera says 16x12");
}

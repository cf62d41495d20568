// transforms*.json datasets (nerf_synthetic, instant-ngp, nerfstudio) from generated fixtures.
#include <stb/stb_image_write.h>

#include <cmath>

#include "reference/rays/rays.h"
#include "support/captured_stderr.h"
#include "support/dataset_files.h"
#include "support/temp_dir.h"

using namespace vknerf;
using namespace vknerf::test;

namespace {

class DatasetTransforms : public TempDirTest {
 protected:
  // Frames looking at `target` from `count` points on a tilted ring of `radius`, images 8x6.
  json frames(const std::string& prefix, int count, std::array<double, 3> target = {0, 0, 0}, double radius = 4,
              bool transparent = false, uint32_t w = 8, uint32_t h = 6) {
    json out = json::array();
    for (int i = 0; i < count; ++i) {
      double a = 2 * M_PI * i / count + 0.3;
      std::array<double, 3> eye{target[0] + radius * std::cos(a) * 0.8, target[1] + radius * std::sin(a) * 0.8,
                                target[2] + radius * 0.6};
      std::string name = prefix + std::to_string(i);
      writePng(dir() / (name + ".png"), patternImage(w, h, uint32_t(i), transparent));
      out.push_back({{"file_path", "./" + name}, {"transform_matrix", matrixJson(poseLookingAt(eye, target))}});
    }
    return out;
  }
  static std::array<float, 16> asFloat(const json& m) {
    std::array<float, 16> out;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) out[4 * r + c] = float(m[r][c].get<double>());
    return out;
  }
};

// Intrinsics are computed in double and rounded once to float: a few float ulps.
constexpr float kIntrinsicsRel = 1e-6f;

}  // namespace

TEST_F(DatasetTransforms, NerfSyntheticSplitFiles) {
  const double angle = 0.6911112070083618;
  json train{{"camera_angle_x", angle}, {"frames", frames("train/r_", 3)}};
  writeJson(dir() / "transforms_train.json", train);
  writeJson(dir() / "transforms_val.json", {{"camera_angle_x", angle}, {"frames", frames("val/r_", 1)}});
  writeJson(dir() / "transforms_test.json", {{"camera_angle_x", angle}, {"frames", frames("test/r_", 2)}});

  Dataset d = Dataset::load(dir().string());
  ASSERT_EQ(d.cameras.size(), 3u);
  ASSERT_EQ(d.images.size(), 3u);
  const float fx = float(0.5 * 8 / std::tan(0.5 * angle));
  for (size_t i = 0; i < 3; ++i) {
    const Camera& c = d.cameras[i];
    EXPECT_NEAR(c.fx, fx, kIntrinsicsRel * fx);
    EXPECT_EQ(c.fy, c.fx);  // square pixels when only camera_angle_x is given
    EXPECT_EQ(c.cx, 4.0f);
    EXPECT_EQ(c.cy, 3.0f);
    EXPECT_EQ(c.width, 8u);
    EXPECT_EQ(c.height, 6u);
    EXPECT_EQ(c.c2w, asFloat(train["frames"][i]["transform_matrix"]));
    EXPECT_EQ(d.images[i].rgba, patternImage(8, 6, uint32_t(i)).rgba);
    EXPECT_EQ(fs::path(d.names[i]), dir() / "./train" / ("r_" + std::to_string(i) + ".png"));
  }
  EXPECT_EQ(d.boundsSource, "cameras");

  EXPECT_EQ(Dataset::load(dir().string(), {.split = "test"}).cameras.size(), 2u);
  EXPECT_EQ(Dataset::load(dir().string(), {.split = "val"}).cameras.size(), 1u);
  Dataset all = Dataset::load(dir().string(), {.split = "all"});
  EXPECT_EQ(all.cameras.size(), 6u);
  // Every split places the box from all cameras of the scene, so they agree.
  Dataset test = Dataset::load(dir().string(), {.split = "test"});
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(test.bounds.min[k], d.bounds.min[k]);
    EXPECT_EQ(test.bounds.max[k], d.bounds.max[k]);
  }
}

TEST_F(DatasetTransforms, PathToSplitFileLoadsThatFile) {
  writeJson(dir() / "transforms_train.json", {{"camera_angle_x", 0.7}, {"frames", frames("train/r_", 3)}});
  writeJson(dir() / "transforms_test.json", {{"camera_angle_x", 0.7}, {"frames", frames("test/r_", 2)}});
  Dataset d = Dataset::load((dir() / "transforms_test.json").string());
  ASSERT_EQ(d.cameras.size(), 2u);
  EXPECT_NE(d.names[0].find("test"), std::string::npos);
  EXPECT_EQ(Dataset::load((dir() / "transforms_train.json").string()).cameras.size(), 3u);
}

TEST_F(DatasetTransforms, InstantNgpIntrinsicsAndPerFrameOverrides) {
  json fr = frames("images/f", 4);
  fr[1]["fl_x"] = 9.0;
  fr[1]["cx"] = 4.25;
  fr[2]["camera_angle_x"] = 1.0;  // replaces the inherited fl_x
  fr[2]["camera_angle_y"] = 0.8;
  fr[3]["fl_y"] = 5.5;
  json j{{"fl_x", 7.0}, {"fl_y", 6.5}, {"cx", 3.75}, {"cy", 3.125}, {"w", 8}, {"h", 6},
         {"k1", 0}, {"k2", 0}, {"p1", 0}, {"p2", 0}, {"camera_model", "OPENCV"}, {"frames", fr}};
  writeJson(dir() / "transforms.json", j);
  Dataset d = Dataset::load(dir().string(), {.split = "all"});
  ASSERT_EQ(d.cameras.size(), 4u);
  const Camera* c = d.cameras.data();
  EXPECT_EQ(c[0].fx, 7.0f);
  EXPECT_EQ(c[0].fy, 6.5f);
  EXPECT_EQ(c[0].cx, 3.75f);
  EXPECT_EQ(c[0].cy, 3.125f);
  EXPECT_EQ(c[1].fx, 9.0f);
  EXPECT_EQ(c[1].fy, 6.5f);
  EXPECT_EQ(c[1].cx, 4.25f);
  EXPECT_NEAR(c[2].fx, 0.5 * 8 / std::tan(0.5), kIntrinsicsRel * c[2].fx);
  EXPECT_NEAR(c[2].fy, 0.5 * 6 / std::tan(0.4), kIntrinsicsRel * c[2].fy);
  EXPECT_EQ(c[2].cx, 3.75f);
  EXPECT_EQ(c[3].fx, 7.0f);
  EXPECT_EQ(c[3].fy, 5.5f);
}

// instant-ngp's keys: k1 k2 [k3] p1 p2 at the top level, overridden per frame; is_fisheye makes
// k1..k4 the fisheye's. Downscaling keeps the coefficients.
TEST_F(DatasetTransforms, InstantNgpLensKeys) {
  json fr = frames("images/f", 3);
  fr[1]["k1"] = -0.05;
  fr[2]["is_fisheye"] = true;
  fr[2]["p1"] = 0;
  fr[2]["p2"] = 0;
  fr[2]["k4"] = -0.0002;
  json j{{"fl_x", 7.0}, {"fl_y", 6.5}, {"w", 8}, {"h", 6}, {"k1", -0.1}, {"k2", 0.02}, {"k3", -0.003},
         {"p1", 0.001}, {"p2", -0.002}, {"frames", fr}};
  writeJson(dir() / "transforms.json", j);
  for (uint32_t downscale : {1u, 2u}) {
    Dataset d = Dataset::load(dir().string(), {.split = "all", .downscale = downscale});
    ASSERT_EQ(d.cameras.size(), 3u);
    const Lens& a = d.cameras[0].lens;
    EXPECT_EQ(a.model, LensModel::OpenCV);
    EXPECT_EQ(a.k1, -0.1f);
    EXPECT_EQ(a.k2, 0.02f);
    EXPECT_EQ(a.k3, -0.003f);
    EXPECT_EQ(a.p1, 0.001f);
    EXPECT_EQ(a.p2, -0.002f);
    EXPECT_EQ(d.cameras[1].lens.k1, -0.05f);
    EXPECT_EQ(d.cameras[1].lens.k2, 0.02f);
    const Lens& f = d.cameras[2].lens;
    EXPECT_EQ(f.model, LensModel::Fisheye);
    EXPECT_EQ(f.k1, -0.1f);
    EXPECT_EQ(f.k3, -0.003f);
    EXPECT_EQ(f.k4, -0.0002f);
    EXPECT_EQ(d.cameras[0].fx, 7.0f / float(downscale));
  }
}

// nerfstudio's camera_model: OPENCV reads k1 k2 k3 p1 p2, OPENCV_FISHEYE k1..k4; a lens whose
// coefficients are all zero is a pinhole.
TEST_F(DatasetTransforms, NerfstudioCameraModels) {
  json j{{"camera_model", "OPENCV"}, {"fl_x", 7.0}, {"fl_y", 7.0}, {"cx", 4.0}, {"cy", 3.0}, {"w", 8}, {"h", 6},
         {"k1", 0.05}, {"k2", -0.01}, {"k3", 0.002}, {"k4", 0}, {"p1", -0.0005}, {"p2", 0.0007}, {"frames", frames("f", 2)}};
  writeJson(dir() / "transforms.json", j);
  Lens l = Dataset::load(dir().string(), {.split = "all"}).cameras[0].lens;
  EXPECT_EQ(l.model, LensModel::OpenCV);
  EXPECT_EQ(l.k1, 0.05f);
  EXPECT_EQ(l.k2, -0.01f);
  EXPECT_EQ(l.k3, 0.002f);
  EXPECT_EQ(l.p1, -0.0005f);
  EXPECT_EQ(l.p2, 0.0007f);
  j["camera_model"] = "OPENCV_FISHEYE";
  j["k4"] = 0.0003;
  j.erase("p1");
  j.erase("p2");
  writeJson(dir() / "transforms.json", j);
  l = Dataset::load(dir().string(), {.split = "all"}).cameras[1].lens;
  EXPECT_EQ(l.model, LensModel::Fisheye);
  EXPECT_EQ(l.k1, 0.05f);
  EXPECT_EQ(l.k4, 0.0003f);
  EXPECT_EQ(l.p1, 0.0f);
  j["camera_model"] = "PINHOLE";
  for (const char* k : {"k1", "k2", "k3", "k4"}) j.erase(k);
  writeJson(dir() / "transforms.json", j);
  EXPECT_EQ(Dataset::load(dir().string(), {.split = "all"}).cameras[0].lens.model, LensModel::Pinhole);
}

TEST_F(DatasetTransforms, FilePathsWithAndWithoutExtensions) {
  auto m = matrixJson(poseLookingAt({0, -4, 1}, {0, 0, 0}));
  writePng(dir() / "a.png", patternImage(8, 6, 1));
  std::vector<uint8_t> rgb(8 * 6 * 3, 128);
  ASSERT_TRUE(stbi_write_jpg((dir() / "b.jpg").c_str(), 8, 6, 3, rgb.data(), 95));
  writePng(dir() / "c.png", patternImage(8, 6, 3));
  fs::create_directories(dir() / "sub");
  ASSERT_TRUE(stbi_write_jpg((dir() / "sub" / "d.jpeg").c_str(), 8, 6, 3, rgb.data(), 95));
  json fr = json::array();
  for (const char* p : {"a", "./b", "c.png", "sub/d"}) fr.push_back({{"file_path", p}, {"transform_matrix", m}});
  writeJson(dir() / "transforms.json", {{"camera_angle_x", 0.7}, {"frames", fr}});
  Dataset d = Dataset::load((dir() / "transforms.json").string(), {.split = "all"});
  ASSERT_EQ(d.names.size(), 4u);
  EXPECT_EQ(fs::path(d.names[0]).filename(), "a.png");
  EXPECT_EQ(fs::path(d.names[1]).filename(), "b.jpg");
  EXPECT_EQ(fs::path(d.names[2]).filename(), "c.png");
  EXPECT_EQ(fs::path(d.names[3]).filename(), "d.jpeg");
  EXPECT_NEAR(d.images[1].rgba[0], 128, 3);  // the JPEG's flat grey
  EXPECT_EQ(d.images[2].rgba, patternImage(8, 6, 3).rgba);
}

// A transforms.json written on its author's machine names its photos there: absolute paths that
// do not exist here. The files of those names beside the json, or in its images/, stand in, with
// one line on stderr per json; an absolute path that exists is taken as it is.
TEST_F(DatasetTransforms, AbsolutePathsFromAnotherMachineFallBackToTheFilesOfThoseNames) {
  const std::string away = "/nonexistent-vknerf-author/cap/images/";
  ASSERT_FALSE(fs::exists(away));
  auto m = matrixJson(poseLookingAt({0, -4, 1}, {0, 0, 0}));
  // In images/: three frames, one without its extension as nerf_synthetic writes them.
  for (int i = 0; i < 3; ++i) writePng(dir() / "images" / ("f" + std::to_string(i) + ".png"), patternImage(8, 6, uint32_t(i)));
  json fr = json::array();
  for (const char* name : {"f0.png", "f1", "f2.png"}) fr.push_back({{"file_path", away + name}, {"transform_matrix", m}});
  // An absolute path that exists, though a file of its name is in images/ too: taken as it is.
  writePng(dir() / "elsewhere" / "f0.png", patternImage(8, 6, 9));
  fr.push_back({{"file_path", (dir() / "elsewhere" / "f0.png").string()}, {"transform_matrix", m}});
  writeJson(dir() / "transforms.json", {{"camera_angle_x", 0.7}, {"frames", fr}});
  Dataset d;
  std::string said = stderrOf([&] { d = Dataset::load(dir().string(), {.split = "all"}); });
  ASSERT_EQ(d.names.size(), 4u);
  EXPECT_EQ(d.names[0], (dir() / "images" / "f0.png").string());
  EXPECT_EQ(d.names[1], (dir() / "images" / "f1.png").string());
  EXPECT_EQ(d.names[2], (dir() / "images" / "f2.png").string());
  EXPECT_EQ(d.names[3], (dir() / "elsewhere" / "f0.png").string());
  EXPECT_EQ(d.images[1].rgba, patternImage(8, 6, 1).rgba);
  EXPECT_EQ(d.images[3].rgba, patternImage(8, 6, 9).rgba);
  EXPECT_EQ(said, "vknerf: " + (dir() / "transforms.json").string() +
                      ": 3 file_path entries are absolute paths that do not exist here; using the files of those names in " +
                      (dir() / "images").string() + "/\n");
  // Once: loading the scene again says nothing more.
  EXPECT_EQ(stderrOf([&] { Dataset::load(dir().string(), {.split = "train"}); }), "");

  // Beside the json, which comes before its images/.
  const fs::path beside = dir() / "beside";
  writePng(beside / "g0.png", patternImage(8, 6, 4));
  writePng(beside / "images" / "g0.png", patternImage(8, 6, 5));
  writeJson(beside / "transforms.json", {{"camera_angle_x", 0.7}, {"frames", {{{"file_path", away + "g0.png"}, {"transform_matrix", m}}}}});
  said = stderrOf([&] { d = Dataset::load(beside.string(), {.split = "all"}); });
  ASSERT_EQ(d.names.size(), 1u);
  EXPECT_EQ(d.names[0], (beside / "g0.png").string());
  EXPECT_EQ(d.images[0].rgba, patternImage(8, 6, 4).rgba);
  EXPECT_EQ(said, "vknerf: " + (beside / "transforms.json").string() +
                      ": 1 file_path entry is an absolute path that does not exist here; using the files of those names beside it\n");
}

TEST_F(DatasetTransforms, HoldoutSplitIsEvenlySpacedAndDisjoint) {
  writeJson(dir() / "transforms.json", {{"camera_angle_x", 0.7}, {"frames", frames("f", 10)}});
  auto names = [&](DatasetOptions o) { return Dataset::load(dir().string(), o).names; };
  auto idx = [](const std::vector<std::string>& v) {
    std::vector<int> out;
    for (auto& n : v) out.push_back(std::stoi(fs::path(n).stem().string().substr(1)));
    return out;
  };
  // Default: 10% of 10 frames = 1 held out, the middle of the single run of 10 (index 5).
  EXPECT_EQ(idx(names({.split = "test"})), (std::vector<int>{5}));
  EXPECT_EQ(idx(names({.split = "val"})), (std::vector<int>{5}));
  EXPECT_EQ(idx(names({.split = "train"})), (std::vector<int>{0, 1, 2, 3, 4, 6, 7, 8, 9}));
  // 30%: three runs of 10/3 frames, the middle of each: floor(1.67), floor(5), floor(8.33).
  EXPECT_EQ(idx(names({.split = "test", .holdoutFraction = 0.3f})), (std::vector<int>{1, 5, 8}));
  EXPECT_EQ(idx(names({.split = "train", .holdoutFraction = 0.3f})), (std::vector<int>{0, 2, 3, 4, 6, 7, 9}));
  EXPECT_EQ(names({.split = "all"}).size(), 10u);
  EXPECT_EQ(names({.split = "train", .holdoutFraction = 0}).size(), 10u);
  EXPECT_EQ(names({.split = "test", .holdoutFraction = 0.3f}), names({.split = "test", .holdoutFraction = 0.3f}));
}

TEST_F(DatasetTransforms, DownscaleScalesImagesAndIntrinsics) {
  json fr = frames("f", 2, {0, 0, 0}, 4, true, 12, 9);
  writeJson(dir() / "transforms.json", {{"camera_angle_x", 0.7}, {"cx", 5.5}, {"cy", 4.0}, {"frames", fr}});
  Dataset full = Dataset::load(dir().string(), {.split = "all"});
  for (uint32_t n : {2u, 3u}) {
    Dataset d = Dataset::load(dir().string(), {.split = "all", .downscale = n});
    ASSERT_EQ(d.cameras.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
      const Camera &c = d.cameras[i], &f = full.cameras[i];
      EXPECT_EQ(c.width, 12 / n);
      EXPECT_EQ(c.height, 9 / n);
      EXPECT_NEAR(c.fx, f.fx / n, kIntrinsicsRel * f.fx);
      EXPECT_NEAR(c.cx, f.cx / n, kIntrinsicsRel * f.cx);
      EXPECT_NEAR(c.cy, f.cy / n, kIntrinsicsRel * f.cy);
      EXPECT_EQ(d.images[i].rgba, vknerf::downscaleImage(full.images[i], n).rgba);
      if (n == 3) {
        // The centre of downscaled pixel (x, y) is the centre of full-resolution pixel (3x+1, 3y+1):
        // both rays agree to float rounding of the intrinsics.
        for (uint32_t y = 0; y < c.height; ++y)
          for (uint32_t x = 0; x < c.width; ++x) {
            auto a = ref::cameraRay<double>(c, x, y), b = ref::cameraRay<double>(f, 3 * x + 1, 3 * y + 1);
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.d[k], b.d[k], 1e-6);
          }
      }
    }
  }
}

TEST_F(DatasetTransforms, AlphaIsKept) {
  writeJson(dir() / "transforms.json", {{"camera_angle_x", 0.7}, {"frames", frames("f", 2, {0, 0, 0}, 4, true)}});
  Dataset d = Dataset::load(dir().string(), {.split = "all"});
  for (uint32_t i = 0; i < 2; ++i) {
    EXPECT_EQ(d.images[i].rgba, patternImage(8, 6, i, true).rgba);
    EXPECT_EQ(d.images[i].rgba[3], 0);  // the transparent left third
  }
}

TEST_F(DatasetTransforms, BoundsFromJsonAabb) {
  writeJson(dir() / "transforms.json", {{"camera_angle_x", 0.7},
                                        {"aabb", {{-1, -2, -3}, {4, 5, 6}}},
                                        {"aabb_scale", 16},
                                        {"frames", frames("f", 3)}});
  Dataset d = Dataset::load(dir().string());
  EXPECT_EQ(d.boundsSource, "json aabb");  // "aabb" wins over aabb_scale
  EXPECT_EQ(d.bounds.min, (std::array<float, 3>{-1, -2, -3}));
  EXPECT_EQ(d.bounds.max, (std::array<float, 3>{4, 5, 6}));
}

TEST_F(DatasetTransforms, BoundsFromInstantNgpScaleAndOffset) {
  // ngp maps p -> p * scale + offset and keeps the cube of side aabb_scale centred at 0.5, so the
  // box in the file's frame is ((0.5 -+ aabb_scale / 2) - offset) / scale per axis.
  writeJson(dir() / "transforms.json", {{"camera_angle_x", 0.7},
                                        {"aabb_scale", 4},
                                        {"scale", 0.5},
                                        {"offset", {0.5, 0.6, 0.7}},
                                        {"frames", frames("f", 3)}});
  Dataset d = Dataset::load(dir().string());
  EXPECT_EQ(d.boundsSource, "aabb_scale");
  const double lo[3] = {-4.0, -4.2, -4.4}, hi[3] = {4.0, 3.8, 3.6};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(d.bounds.min[k], lo[k], 1e-6);
    EXPECT_NEAR(d.bounds.max[k], hi[k], 1e-6);
  }
  // ngp's defaults: scale 0.33, offset 0.5: aabb_scale 2 is +-1 / 0.33.
  writeJson(dir() / "transforms.json", {{"camera_angle_x", 0.7}, {"aabb_scale", 2}, {"frames", frames("f", 3)}});
  Dataset e = Dataset::load(dir().string());
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(e.bounds.min[k], -1 / 0.33, 1e-5);
    EXPECT_NEAR(e.bounds.max[k], 1 / 0.33, 1e-5);
  }
}

TEST_F(DatasetTransforms, BoundsFromCamerasCentreOnTheirTarget) {
  // Eight cameras 4 units from (1, -0.5, 2), all looking at it: the optical axes meet there, and
  // the half extent is distance * tan(half the horizontal field of view) (the wider one, w > h).
  const std::array<double, 3> target{1, -0.5, 2};
  writeJson(dir() / "transforms.json", {{"camera_angle_x", 0.8}, {"frames", frames("f", 8, target)}});
  Dataset d = Dataset::load(dir().string(), {.split = "all"});
  EXPECT_EQ(d.boundsSource, "cameras");
  const double half = 4 * std::tan(0.4);
  for (int k = 0; k < 3; ++k) {
    // Float poses put the axes' meeting point within ~1e-6 of the target; the regularising pull
    // (weight 1e-3 per camera) moves it by at most ~1e-3 of the prior's distance.
    EXPECT_NEAR(0.5 * (d.bounds.min[k] + d.bounds.max[k]), target[k], 5e-3);
    EXPECT_NEAR(0.5 * (d.bounds.max[k] - d.bounds.min[k]), half, 5e-3 * half);
  }
}

TEST_F(DatasetTransforms, BoundsFromOneOrParallelCamerasAreFiniteAndInFront) {
  // One camera, or two looking the same way, do not fix the point the axes meet: the box must
  // still be finite, non-empty and in front of the cameras.
  for (int count : {1, 2}) {
    json fr = json::array();
    for (int i = 0; i < count; ++i) {
      auto m = poseLookingAt({double(i), -5, 0}, {double(i), 0, 0});
      writePng(dir() / ("p" + std::to_string(i) + ".png"), patternImage(8, 6, 0));
      fr.push_back({{"file_path", "p" + std::to_string(i)}, {"transform_matrix", matrixJson(m)}});
    }
    writeJson(dir() / "transforms.json", {{"camera_angle_x", 0.7}, {"frames", fr}});
    Dataset d = Dataset::load(dir().string(), {.split = "all"});
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(std::isfinite(d.bounds.min[k]) && std::isfinite(d.bounds.max[k]));
      EXPECT_LT(d.bounds.min[k], d.bounds.max[k]);
    }
    EXPECT_GT(0.5 * (d.bounds.min[1] + d.bounds.max[1]), -5);  // the cameras look along +y from y = -5
  }
}

TEST_F(DatasetTransforms, AlphaMasksCarveTheBoxToTheObject) {
  // A sphere of radius 0.5 at c0 seen by 40 cameras spread over a sphere of radius 3 around it
  // (Fibonacci lattice); alpha is 255 where a pixel's centre ray hits the sphere, 0 elsewhere.
  const std::array<double, 3> c0{0.3, -0.2, 0.1};
  const double r = 0.5, dist = 3, angle = 0.9;
  const uint32_t size = 40, count = 40;
  json fr = json::array();
  for (uint32_t i = 0; i < count; ++i) {
    double z = 1 - 2 * (i + 0.5) / count, rho = std::sqrt(1 - z * z), phi = i * M_PI * (3 - std::sqrt(5.0));
    std::array<double, 3> eye{c0[0] + dist * rho * std::cos(phi), c0[1] + dist * rho * std::sin(phi), c0[2] + dist * z};
    Camera cam;
    cam.width = cam.height = size;
    cam.fx = cam.fy = float(0.5 * size / std::tan(0.5 * angle));
    cam.cx = cam.cy = 0.5f * size;
    auto m = poseLookingAt(eye, c0);
    for (int k = 0; k < 16; ++k) cam.c2w[k] = float(m[k]);
    ImageRGBA8 img{size, size, std::vector<uint8_t>(size * size * 4, 255)};
    for (uint32_t y = 0; y < size; ++y)
      for (uint32_t x = 0; x < size; ++x) {
        auto ray = ref::cameraRay<double>(cam, x, y);
        double oc[3] = {ray.o[0] - c0[0], ray.o[1] - c0[1], ray.o[2] - c0[2]};
        double b = oc[0] * ray.d[0] + oc[1] * ray.d[1] + oc[2] * ray.d[2];
        double c = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - r * r;
        img.rgba[(y * size + x) * 4 + 3] = b * b - c >= 0 ? 255 : 0;
      }
    std::string name = "s" + std::to_string(i);
    writePng(dir() / (name + ".png"), img);
    fr.push_back({{"file_path", name}, {"transform_matrix", matrixJson(m)}});
  }
  writeJson(dir() / "transforms.json", {{"camera_angle_x", angle}, {"frames", fr}});
  Dataset d = Dataset::load(dir().string(), {.split = "all"});
  EXPECT_EQ(d.boundsSource, "cameras+alpha");
  // Conservative: the sphere is inside, up to the one-pixel footprint at the sphere's distance that
  // a pixel-centre mask can miss (3 * 2 tan(0.45) / 40 = 0.073). Tight: within two 64^3 grid cells
  // (the grid spans the camera box, 2 * 3 tan(0.45) / 64 = 0.045 per cell) and two pixels of
  // silhouette, far inside the camera-only box (half extent 1.45).
  const double pixel = dist * 2 * std::tan(0.5 * angle) / size, cell = 2 * dist * std::tan(0.5 * angle) / 64;
  for (int k = 0; k < 3; ++k) {
    EXPECT_LE(d.bounds.min[k], c0[k] - r + pixel);
    EXPECT_GE(d.bounds.max[k], c0[k] + r - pixel);
    EXPECT_GE(d.bounds.min[k], c0[k] - r - 2 * cell - 2 * pixel);
    EXPECT_LE(d.bounds.max[k], c0[k] + r + 2 * cell + 2 * pixel);
  }
}

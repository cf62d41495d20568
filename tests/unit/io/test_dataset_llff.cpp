// LLFF's poses_bounds.npy. Photos rendered from known cameras, written both as transforms.json and
// as poses_bounds.npy, load to the same cameras and the same rays, and those rays are the renderer's;
// the [down, right, back] convention on a hand-written row; float32, format 2.0 and Fortran order;
// images_N/ read as they are with the focal length scaled, with or without images/ beside them;
// llffhold 8; the box of the frustums; and every bad file an error naming the file and the field.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "gpu/memory/buffer.h"
#include "io/dataset/dataset_loaders.h"
#include "vknerf/image_io.h"
#include "nerf/rays/rays.h"
#include "reference/rays/rays.h"
#include "support/captured_stderr.h"
#include "support/cli_run.h"
#include "support/colmap_model_files.h"
#include "support/dataset_checks.h"
#include "support/dataset_files.h"
#include "support/error_message.h"
#include "support/gpu_test.h"
#include "support/llff_files.h"
#include "support/submit_once.h"
#include "support/temp_dir.h"
#include "support/textured_views.h"

using namespace vknerf;
using namespace vknerf::test;

namespace {

using Row = std::array<double, 17>;

DatasetOptions split(const std::string& s, uint32_t downscale = 1) {
  DatasetOptions o;
  o.split = s;
  o.downscale = downscale;
  return o;
}

void writeRows(const fs::path& dir, const std::vector<Row>& rows, const NpyOptions& o = {}) {
  writeText(dir / "poses_bounds.npy", poseBoundsBytes(rows, o));
}

// ---- The same cameras as transforms.json and as poses_bounds.npy ----

constexpr double kNear = 2, kFar = 9;  // the rendered scene lies within 2 units of the origin, the ring at 5
TexturedViewsSpec renderedSpec() {
  TexturedViewsSpec s;
  s.views = 9;  // llffhold 8 holds out views 0 and 8
  s.width = 40;
  s.height = 30;
  s.focal = 37.5;  // exact in float, so that both files state the same focal length to the bit
  return s;
}

// Renders the views into dir/images/ and writes their cameras as dir/transforms.json and as
// dir/poses_bounds.npy.
std::vector<TrueView> writeBothForms(const fs::path& dir) {
  const TexturedViewsSpec s = renderedSpec();
  std::vector<TrueView> views = renderTexturedViews(dir / "images", s);
  json frames = json::array();
  std::vector<Row> rows;
  for (const TrueView& v : views) {
    frames.push_back({{"file_path", "images/" + v.name}, {"transform_matrix", matrixJson(v.c2w)}});
    rows.push_back(llffRow(v.c2w, s.height, s.width, s.focal, kNear, kFar));
  }
  writeJson(dir / "transforms.json", {{"fl_x", s.focal}, {"fl_y", s.focal}, {"w", s.width}, {"h", s.height}, {"frames", frames}});
  writeRows(dir, rows);
  return views;
}

// The ray the renderer traced through pixel position (px, py) of view v (textured_views.cpp).
ref::Ray<double> trueRay(const TrueView& v, const TexturedViewsSpec& s, double px, double py) {
  const auto& m = v.c2w;
  const double dc[3] = {(px - 0.5 * s.width) / s.focal, -(py - 0.5 * s.height) / s.focal, -1};
  ref::Ray<double> r;
  double n = 0;
  for (int k = 0; k < 3; ++k) {
    r.o[k] = m[4 * k + 3];
    r.d[k] = m[4 * k] * dc[0] + m[4 * k + 1] * dc[1] + m[4 * k + 2] * dc[2];
    n += r.d[k] * r.d[k];
  }
  for (double& d : r.d) d /= std::sqrt(n);
  return r;
}

// The loaded cameras hold the true poses rounded to floats (relative error 2^-24 per entry) and the
// device computes the direction in floats over O(1) values: a few 1e-7 in all, as test_rays bounds
// the device against the double reference (2e-6). A wrong axis order or sign is wrong by the angle
// between two pixels' rays at the least, 0.5 / 37.5 > 1e-2.
constexpr double kRayTol = 2e-6;

std::vector<float> deviceRays(Context& ctx, const Dataset& d, uint32_t camera, const Aabb& box) {
  const auto packed = nerf::packCameras(d.cameras);
  auto cameras = gpu::Buffer::of(ctx, packed);
  const uint32_t count = d.cameras[camera].width * d.cameras[camera].height;
  gpu::Buffer rays(ctx, count * nerf::kRayBytes), ids(ctx, count * nerf::kPixelIdBytes);
  nerf::RayGeneration gen(ctx);
  submitOnce(ctx, [&](gpu::Recorder& rec) { gen.recordImage(rec, cameras, {camera, 0, count}, {box, 0.0f}, {rays, ids}); });
  return rays.download<float>(count * 8);
}

class LlffRays : public GpuTest {
 protected:
  TempDir dir_{"llff_rays"};
};

// A folder of `count` photos of width x height named name(i), a distinct pattern each.
void writePhotos(const fs::path& folder, int count, uint32_t w, uint32_t h, uint32_t seed, const char* format) {
  for (int i = 0; i < count; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, format, i);
    writePng(folder / name, patternImage(w, h, seed + uint32_t(i)));
  }
}

// Three cameras looking at the origin with hwf (6, 8, 10) and bounds (1, 8), photos images/p0..2.png.
std::vector<Row> smallRows() {
  std::vector<Row> rows;
  for (const auto& eye : {std::array<double, 3>{4, 0, 0}, {0, 4, 1}, {-3, 0, 2}})
    rows.push_back(llffRow(poseLookingAt(eye, {0, 0, 0}), 6, 8, 10, 1, 8));
  return rows;
}

void writeSmallScene(const fs::path& dir) {
  writePhotos(dir / "images", 3, 8, 6, 0, "p%d.png");
  writeRows(dir, smallRows());
}

}  // namespace

TEST_F(LlffRays, SameCamerasAndRaysAsTransformsJsonAndTheRenderersRays) {
  const fs::path dir = dir_.path();
  const std::vector<TrueView> views = writeBothForms(dir);
  const TexturedViewsSpec s = renderedSpec();
  const Dataset fromJson = Dataset::load(dir / "transforms.json", split("all"));
  // The folder holds both files, and transforms.json comes first: the .npy is named.
  const Dataset llff = Dataset::load(dir / "poses_bounds.npy", split("all"));
  ASSERT_EQ(llff.cameras.size(), views.size());
  // Every camera bit for bit: both files carry the same doubles (the conversion only moves and
  // negates them), rounded to floats once.
  expectSameViews(fromJson, llff);
  EXPECT_EQ(llff.boundsSource, "llff bounds");
  ASSERT_EQ(llff.depthBounds.size(), views.size());
  for (const auto& b : llff.depthBounds) EXPECT_EQ(b, (std::array<float, 2>{float(kNear), float(kFar)}));
  EXPECT_TRUE(fromJson.depthBounds.empty());

  for (uint32_t c = 0; c < views.size(); ++c) {
    SCOPED_TRACE("camera " + std::to_string(c));
    // The device's rays of both loads, bit for bit (same cameras, same box, same shader), and the
    // renderer's rays through every pixel centre.
    const std::vector<float> a = deviceRays(ctx(), fromJson, c, llff.bounds), b = deviceRays(ctx(), llff, c, llff.bounds);
    ASSERT_EQ(a, b);
    for (uint32_t p = 0; p < uint32_t(s.width * s.height); ++p) {
      const auto truth = trueRay(views[c], s, p % s.width + 0.5, p / s.width + 0.5);
      for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(near(b[8 * p + k], truth.o[k], kRayTol, kRayTol)) << "pixel " << p;
        EXPECT_TRUE(near(b[8 * p + 4 + k], truth.d[k], kRayTol, kRayTol)) << "pixel " << p;
      }
    }
    // The CPU reference through the image corners, where an error in the focal length or the
    // principal point shows most.
    for (double px : {0.0, double(s.width)})
      for (double py : {0.0, double(s.height)}) {
        const auto r = ref::cameraRayAt<double>(llff.cameras[c], px, py), truth = trueRay(views[c], s, px, py);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.d[k], truth.d[k], kRayTol);
      }
  }

  // The papers' split: views 0 and 8 are held out.
  const Dataset test = Dataset::load(dir / "poses_bounds.npy", split("test"));
  ASSERT_EQ(test.names.size(), 2u);
  EXPECT_EQ(fs::path(test.names[0]).filename(), views[0].name);
  EXPECT_EQ(fs::path(test.names[1]).filename(), views[8].name);
}

TEST(DatasetLlff, ColumnsAreDownRightBack) {
  TempDir dir("llff_convention");
  // A camera at (1, 2, 3) whose image's down is world -Z, its right world +X and its back world -Y:
  // it looks along +Y with +Z up.
  Row row{};
  const double down[3] = {0, 0, -1}, right[3] = {1, 0, 0}, back[3] = {0, -1, 0}, t[3] = {1, 2, 3}, hwf[3] = {6, 8, 10};
  for (int k = 0; k < 3; ++k) {
    row[5 * k] = down[k];
    row[5 * k + 1] = right[k];
    row[5 * k + 2] = back[k];
    row[5 * k + 3] = t[k];
    row[5 * k + 4] = hwf[k];
  }
  row[15] = 0.5;
  row[16] = 4;
  writeRows(dir.path(), {row});
  writePhotos(dir.path() / "images", 1, 8, 6, 0, "p%d.png");
  const Dataset d = Dataset::load(dir.path(), split("all"));
  ASSERT_EQ(d.cameras.size(), 1u);
  const Camera& c = d.cameras[0];
  const std::array<float, 16> expected{1, 0, 0, 1, 0, 0, -1, 2, 0, 1, 0, 3, 0, 0, 0, 1};
  EXPECT_EQ(c.c2w, expected);
  EXPECT_EQ(c.fx, 10);
  EXPECT_EQ(c.fy, 10);
  EXPECT_EQ(c.cx, 4);
  EXPECT_EQ(c.cy, 3);
  // The image's centre looks along +Y, its right edge leans to +X, its bottom edge to -Z.
  const auto centre = ref::cameraRayAt<double>(c, 4, 3), rightEdge = ref::cameraRayAt<double>(c, 8, 3),
             bottomEdge = ref::cameraRayAt<double>(c, 4, 6);
  EXPECT_NEAR(centre.d[1], 1, 1e-12);
  EXPECT_NEAR(rightEdge.d[0], 0.4 / std::sqrt(1.16), 1e-12);
  EXPECT_NEAR(bottomEdge.d[2], -0.3 / std::sqrt(1.09), 1e-12);
}

TEST(DatasetLlff, Float32FormatTwoAndFortranOrderReadAlike) {
  TempDir dir("llff_forms");
  writePhotos(dir.path() / "images", 3, 8, 6, 0, "p%d.png");
  // Rotations about each axis (entries 0, +-1, +-0.6, +-0.8) and translations, hwf and bounds that
  // floats hold exactly: a value stored as float32 is the float the loader rounds the float64 to.
  std::vector<Row> rows;
  const std::array<double, 16> a{1, 0, 0, 2, 0, 0.6, -0.8, 0.5, 0, 0.8, 0.6, 4, 0, 0, 0, 1},
      b{0.8, 0, 0.6, -1, 0, 1, 0, 0.25, -0.6, 0, 0.8, 3, 0, 0, 0, 1}, c{0, -1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 5, 0, 0, 0, 1};
  for (const auto& m : {a, b, c}) rows.push_back(llffRow(m, 6, 8, 10.5, 0.75, 6));
  writeRows(dir.path(), rows);
  const Dataset reference = Dataset::load(dir.path(), split("all"));
  for (const NpyOptions& o : {NpyOptions{true, 1, false}, NpyOptions{false, 2, false}, NpyOptions{false, 1, true},
                              NpyOptions{true, 2, true}}) {
    SCOPED_TRACE("float32 " + std::to_string(o.float32) + ", version " + std::to_string(o.version) + ", fortran " +
                 std::to_string(o.fortran));
    writeRows(dir.path(), rows, o);
    const Dataset d = Dataset::load(dir.path(), split("all"));
    expectSameCameras(reference, d);
    EXPECT_EQ(reference.depthBounds, d.depthBounds);
  }
  for (int k = 0; k < 3; ++k) EXPECT_EQ(reference.cameras[1].c2w[4 * k + 3], float(b[4 * k + 3]));
}

TEST(DatasetLlff, ImagesNAreReadAsTheyAreWithTheFocalLengthScaled) {
  TempDir dir("llff_images_n");
  const fs::path p = dir.path();
  writeSmallScene(p);  // images/p0..2.png at 8x6, hwf (6, 8, 10)
  std::vector<Row> rows = smallRows();
  for (Row& r : rows) r[14] = 10.25;  // a focal length whose scaled values are not round
  writeRows(p, rows);
  // LLFF's images_N/ names its photos differently from images/: they pair by sorted order.
  writePhotos(p / "images_2", 3, 4, 3, 100, "image%03d.png");
  writePhotos(p / "images_3", 3, 3, 2, 200, "image%03d.png");  // 8 / 3 and 6 / 3 rounded: 3 x 2
  const Dataset full = Dataset::load(p, split("all"));

  for (uint32_t n : {2u, 3u}) {
    SCOPED_TRACE("downscale " + std::to_string(n));
    const Dataset d = Dataset::load(p, split("all", n));
    ASSERT_EQ(d.cameras.size(), 3u);
    const uint32_t w = n == 2 ? 4 : 3, h = n == 2 ? 3 : 2;
    for (uint32_t i = 0; i < 3; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "image%03u.png", i);
      EXPECT_EQ(d.names[i], (p / ("images_" + std::to_string(n)) / name).string());
      // The photo as stored, not resampled.
      EXPECT_EQ(d.images[i].rgba, patternImage(w, h, (n == 2 ? 100 : 200) + i).rgba);
      const Camera& c = d.cameras[i];
      EXPECT_EQ(c.width, w);
      EXPECT_EQ(c.height, h);
      EXPECT_EQ(c.fx, float(10.25 * (w / 8.0)));
      EXPECT_EQ(c.fy, float(10.25 * (h / 6.0)));
      EXPECT_EQ(c.cx, 0.5f * float(w));
      EXPECT_EQ(c.cy, 0.5f * float(h));
      EXPECT_EQ(c.c2w, full.cameras[i].c2w);
    }
    // The frustums are those of the full-size photos: the same box and bounds.
    expectSameBox(d, full);
    EXPECT_EQ(d.depthBounds, full.depthBounds);
  }

  // Without images_4/, images/ is box-filtered as for every format.
  const Dataset boxed = Dataset::load(p, split("all", 4));
  for (uint32_t i = 0; i < 3; ++i) {
    EXPECT_EQ(boxed.names[i], (p / "images" / ("p" + std::to_string(i) + ".png")).string());
    EXPECT_EQ(boxed.images[i].rgba, vknerf::downscaleImage(patternImage(8, 6, i), 4).rgba);
    EXPECT_EQ(boxed.cameras[i].fx, float(10.25) * 0.25f);
    EXPECT_EQ(boxed.cameras[i].width, 2u);
    EXPECT_EQ(boxed.cameras[i].height, 1u);
  }
  expectSameBox(boxed, full);
}

TEST(DatasetLlff, ImagesNMustMatchThePosesAndTheirShape) {
  TempDir dir("llff_images_n_bad");
  const fs::path p = dir.path();
  writeSmallScene(p);
  writePhotos(p / "images_2", 2, 4, 3, 100, "image%03d.png");
  std::string m = errorOf([&] { Dataset::load(p, split("all", 2)); });
  EXPECT_MESSAGE_HAS(m, (p / "images_2").string() + "' holds 2 photos");
  EXPECT_MESSAGE_HAS(m, "poses_bounds.npy' has 3 rows");
  // A copy squeezed in one axis only cannot be one focal length's scaling.
  writePhotos(p / "images_2", 3, 4, 1, 100, "image%03d.png");
  m = errorOf([&] { Dataset::load(p, split("all", 2)); });
  EXPECT_MESSAGE_HAS(m, "poses_bounds.npy: row 0: image '" + (p / "images_2" / "image000.png").string() + "' is 4x1");
  EXPECT_MESSAGE_HAS(m, "not a copy of the 8x6");
}

// Shared as they often are: images_N/ alone, without the full-size photos hwf states. Three rows
// with hwf (24, 32, 30); images_4/ holds them at 8x6 and images_2/ (when written) at 16x12.
std::vector<Row> rowsAt(double height, double width, double focal) {
  std::vector<Row> rows = smallRows();
  for (Row& r : rows) r[4] = height, r[9] = width, r[14] = focal;
  return rows;
}

TEST(DatasetLlff, ImagesNAloneLoadWithHwfScaledToTheirSize) {
  TempDir dir("llff_images_n_only");
  const fs::path p = dir.path();
  writeRows(p, rowsAt(24, 32, 30));
  writePhotos(p / "images_4", 3, 8, 6, 100, "image%03d.png");
  ASSERT_FALSE(fs::exists(p / "images"));

  Dataset d;
  const std::string said = stderrOf([&] { d = Dataset::load(p, split("all")); });
  ASSERT_EQ(d.cameras.size(), 3u);
  for (uint32_t i = 0; i < 3; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "image%03u.png", i);
    EXPECT_EQ(d.names[i], (p / "images_4" / name).string());
    EXPECT_EQ(d.images[i].rgba, patternImage(8, 6, 100 + i).rgba);  // as stored, not resampled
    const Camera& c = d.cameras[i];
    EXPECT_EQ(c.width, 8u);
    EXPECT_EQ(c.height, 6u);
    EXPECT_EQ(c.fx, 7.5f);  // hwf's focal 30 over 4
    EXPECT_EQ(c.fy, 7.5f);
    EXPECT_EQ(c.cx, 4.0f);
    EXPECT_EQ(c.cy, 3.0f);
  }
  // One line naming the folder used, however many photos; not again when the scene loads again.
  EXPECT_EQ(occurrences(said, "\n"), 1u) << said;
  EXPECT_MESSAGE_HAS(said, (p / "poses_bounds.npy").string() + ": no images/ folder beside it; using " +
                               (p / "images_4").string() + "/ (photos 4 times smaller than hwf's 32x24)");
  EXPECT_EQ(stderrOf([&] { Dataset::load(p, split("test")); }), "");

  // Asked for 4: images_4/ as it is, the same cameras, without a note (it is what was asked for).
  const Dataset asked = Dataset::load(p, split("all", 4));
  expectSameCameras(d, asked);
  // Asked for 8: images_4/ shrunk twice more, intrinsics following.
  const Dataset eighth = Dataset::load(p, split("all", 8));
  for (uint32_t i = 0; i < 3; ++i) {
    EXPECT_EQ(eighth.images[i].rgba, vknerf::downscaleImage(patternImage(8, 6, 100 + i), 2).rgba);
    EXPECT_EQ(eighth.cameras[i].width, 4u);
    EXPECT_EQ(eighth.cameras[i].fx, 3.75f);
    EXPECT_EQ(eighth.cameras[i].cx, 2.0f);
  }
  expectSameBox(eighth, d);

  // With images_2/ beside it, the default takes the finest; 4 still takes images_4/.
  writePhotos(p / "images_2", 3, 16, 12, 200, "image%03d.png");
  const Dataset finest = Dataset::load(p, split("all"));
  EXPECT_EQ(fs::path(finest.names[0]).parent_path(), p / "images_2");
  EXPECT_EQ(finest.cameras[0].width, 16u);
  EXPECT_EQ(finest.cameras[0].fx, 15.0f);
  EXPECT_EQ(fs::path(Dataset::load(p, split("all", 4)).names[0]).parent_path(), p / "images_4");
  // 3 is no multiple of 2 or 4: the nearest coarser folder, as it is.
  EXPECT_EQ(fs::path(Dataset::load(p, split("all", 3)).names[0]).parent_path(), p / "images_4");
  // 5 is neither, and no folder is coarser: refused, naming the folders.
  fs::remove_all(p / "images_4");
  const std::string m = errorOf([&] { Dataset::load(p, split("all", 5)); });
  EXPECT_MESSAGE_HAS(m, (p / "poses_bounds.npy").string() + ": no images/ folder beside it, and downscale 5 cannot be made from images_2/");
}

TEST(DatasetLlff, ImagesNWhoseSizeDisagreesWithHwfNameTheField) {
  TempDir dir("llff_images_n_hwf");
  const fs::path p = dir.path();
  // hwf states 64x48, but images_8/ holds 4x3: the aspect agrees, the size is half what hwf / 8 is
  // (hwf written for other photos than these), which would halve every focal length.
  writeRows(p, rowsAt(48, 64, 60));
  writePhotos(p / "images_8", 3, 4, 3, 100, "image%03d.png");
  const std::string image = (p / "images_8" / "image000.png").string();
  std::string m = errorOf([&] { Dataset::load(p, split("all")); });
  EXPECT_EQ(m.rfind((p / "poses_bounds.npy").string() + ": row 0: image '" + image + "' is 4x3 but hwf width 64 / 8 is 8", 0), 0u) << m;
  // The same when images/ is there and images_8/ is asked for.
  writePhotos(p / "images", 3, 64, 48, 0, "p%d.png");
  m = errorOf([&] { Dataset::load(p, split("all", 8)); });
  EXPECT_MESSAGE_HAS(m, "row 0: image '" + image + "' is 4x3 but hwf width 64 / 8 is 8");
  // Rounding is not disagreement: 64 / 3 and 48 / 3 are 21.3 and 16, stored as 21x16 or 22x16.
  for (uint32_t w : {21u, 22u}) {
    writePhotos(p / "images_3", 3, w, 16, 0, "image%03d.png");
    EXPECT_EQ(Dataset::load(p, split("all", 3)).cameras[0].width, w);
  }
  writePhotos(p / "images_3", 3, 20, 16, 0, "image%03d.png");
  EXPECT_MESSAGE_HAS(errorOf([&] { Dataset::load(p, split("all", 3)); }), "is 20x16 but hwf width 64 / 3 is 21.3333");
}

TEST(DatasetLlff, EveryEighthPhotoIsHeldOut) {
  TempDir dir("llff_hold");
  const fs::path p = dir.path();
  std::vector<Row> rows;
  for (int i = 0; i < 17; ++i) rows.push_back(llffRow(poseLookingAt({4, 0.5 * i, 1}, {0, 0, 0}), 3, 4, 5, 1, 6));
  writeRows(p, rows);
  writePhotos(p / "images", 17, 4, 3, 0, "p%02d.png");
  auto indices = [&](const DatasetOptions& o) {
    std::vector<int> out;
    for (const std::string& n : Dataset::load(p, o).names) out.push_back(std::stoi(fs::path(n).stem().string().substr(1)));
    return out;
  };
  const std::vector<int> held{0, 8, 16}, rest{1, 2, 3, 4, 5, 6, 7, 9, 10, 11, 12, 13, 14, 15};
  EXPECT_EQ(indices(split("test")), held);
  EXPECT_EQ(indices(split("val")), held);
  EXPECT_EQ(indices(split("train")), rest);
  EXPECT_EQ(indices(split("all")).size(), 17u);
  DatasetOptions other = split("test");
  other.holdoutFraction = 0.5f;  // the transforms.json / COLMAP holdout; LLFF's split is fixed
  EXPECT_EQ(indices(other), held);
  // Every split has the box of all 17 frustums.
  expectSameBox(Dataset::load(p, split("test")), Dataset::load(p, split("train")));
}

TEST(DatasetLlff, PosesBoundsComeBeforeAColmapModelBesideThem) {
  TempDir dir("llff_dispatch");
  const fs::path p = dir.path();
  writeSmallScene(p);
  ColmapModelRecords model;
  model.cameras = {{1, "PINHOLE", 8, 6, {10, 10, 4, 3}}};
  for (uint32_t i = 0; i < 3; ++i) {
    std::array<double, 16> c2w{};
    const Row r = smallRows()[i];
    for (int k = 0; k < 3; ++k) {
      c2w[4 * k] = r[5 * k + 1];
      c2w[4 * k + 1] = -r[5 * k];
      c2w[4 * k + 2] = r[5 * k + 2];
      c2w[4 * k + 3] = r[5 * k + 3];
    }
    c2w[15] = 1;
    model.images.push_back(imageRecord(i + 1, c2w, 1, "p" + std::to_string(i) + ".png"));
  }
  writeColmapText(p / "sparse" / "0", model);
  EXPECT_EQ(Dataset::load(p, split("all")).boundsSource, "llff bounds");
  EXPECT_EQ(Dataset::load(p / "poses_bounds.npy", split("all")).boundsSource, "llff bounds");
  const Dataset colmap = Dataset::load(p / "sparse" / "0", split("all"));
  EXPECT_EQ(colmap.boundsSource, "cameras");
  EXPECT_TRUE(colmap.depthBounds.empty());
}

// ---- The box of the frustums ----

TEST(DatasetLlff, FrustumBoxOfOneCameraIsItsCorners) {
  // A camera at the origin looking down -Z, 40x30 pixels, focal 20: at depth z its image spans
  // x in +-z, y in +-0.75 z.
  const Camera c = pinholeFromFocal(40, 30, 20);
  const std::array<float, 2> bounds{1, 3};
  const Aabb box = io::detail::boxFromFrustums(std::span(&c, 1), std::span(&bounds, 1));
  EXPECT_EQ(box.min, (std::array<float, 3>{-3, -2.25f, -3}));
  EXPECT_EQ(box.max, (std::array<float, 3>{3, 2.25f, -1}));
}

TEST(DatasetLlff, FrustumBoxHoldsEveryFrustumAndNoMore) {
  std::vector<Camera> cams = {pinholeFromFocal(40, 30, 35, lookAt({4, 1, 2}, {0, 0, 0}, {0, 0, 1})),
                              pinholeFromFocal(20, 50, 18, lookAt({-2, 3, -1}, {0.5f, 0, 0}, {0, 0, 1})),
                              pinholeFromFocal(64, 48, 80, lookAt({0, -5, 0.5f}, {0, 0, 1}, {0, 0, 1}))};
  cams[1].cx = 7.5f;  // an off-centre principal point
  const std::vector<std::array<float, 2>> bounds = {{1, 6}, {0.5f, 3}, {2, 9}};
  const Aabb box = io::detail::boxFromFrustums(cams, bounds);
  // Points of the frustums, reached along the reference's rays: depth z along the axis is distance
  // z / cos on a ray. Every one lies in the box; the corners reach each face (the box is tight).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0, 1);
  std::array<double, 3> lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  for (size_t i = 0; i < cams.size(); ++i) {
    const Camera& c = cams[i];
    const double axis[3] = {-c.c2w[2], -c.c2w[6], -c.c2w[10]};
    auto pointAt = [&](double px, double py, double z) {
      const auto r = ref::cameraRayAt<double>(c, px, py);
      const double cosine = r.d[0] * axis[0] + r.d[1] * axis[1] + r.d[2] * axis[2];
      std::array<double, 3> q;
      for (int k = 0; k < 3; ++k) q[k] = r.o[k] + r.d[k] * z / cosine;
      return q;
    };
    for (int s = 0; s < 2000; ++s) {
      const auto q = pointAt(unit(rng) * c.width, unit(rng) * c.height, bounds[i][0] + unit(rng) * (bounds[i][1] - bounds[i][0]));
      for (int k = 0; k < 3; ++k) {
        EXPECT_GE(q[k], box.min[k]);
        EXPECT_LE(q[k], box.max[k]);
      }
    }
    for (double z : bounds[i])
      for (double px : {0.0, double(c.width)})
        for (double py : {0.0, double(c.height)}) {
          const auto q = pointAt(px, py, z);
          for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], q[k]), hi[k] = std::max(hi[k], q[k]);
        }
  }
  // The corners computed two ways (pixel offsets over the focal length there, a normalised ray
  // over its cosine here) agree to double rounding; the box rounds them outwards to floats, by at
  // most one float spacing, 2^-23 |v| < 1.2e-7 |v|.
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(box.min[k], lo[k], 2.5e-7 * std::max(1.0, std::fabs(lo[k])));
    EXPECT_NEAR(box.max[k], hi[k], 2.5e-7 * std::max(1.0, std::fabs(hi[k])));
  }
}

TEST(DatasetLlff, FrustumBoxRefusesLensesAndMismatchedBounds) {
  Camera c = pinholeFromFocal(8, 6, 10);
  const std::array<float, 2> b{1, 2};
  EXPECT_MESSAGE_HAS(errorOf([&] { io::detail::boxFromFrustums(std::span(&c, 1), {}); }), "one {near, far} per camera");
  c.lens.model = LensModel::OpenCV;
  c.lens.k1 = 0.1f;
  EXPECT_MESSAGE_HAS(errorOf([&] { io::detail::boxFromFrustums(std::span(&c, 1), std::span(&b, 1)); }), "pinhole");
}

// A forward-facing capture's cascades: a 3x3 grid of cameras 0.1 apart looking down -Z, 40x30 at
// focal 20 (frames +-z by +-0.75 z at depth z), near 1 and far 20. The inner cube sits on the axis
// at depth 1.5 (the median near times 1.5) and holds every frame there (x within 1.5 + 0.1 of the
// axis); the box, that cube scaled by a power of two about its centre, holds every frustum out to
// the far bound (the frustum box), and half of it would not.
TEST(DatasetLlff, ForwardFacingBoxNestsCascadesFromTheNearContentOut) {
  std::vector<Camera> cams;
  std::vector<std::array<float, 2>> bounds;
  for (int i = 0; i < 9; ++i) {
    Camera c = pinholeFromFocal(40, 30, 20);
    c.c2w[3] = 0.1f * float(i % 3 - 1);
    c.c2w[7] = 0.1f * float(i / 3 - 1);
    cams.push_back(c);
    bounds.push_back({i == 4 ? 0.8f : 1.0f, 20});
  }
  float scale = 0;
  const Aabb frustums = io::detail::boxFromFrustums(cams, bounds);
  const Aabb box = io::detail::cascadedBoxFromDepths(cams, bounds, frustums, scale);
  ASSERT_GE(scale, 2.0f);
  EXPECT_EQ(std::exp2(std::round(std::log2(scale))), scale) << "a power of two";
  std::array<double, 3> centre, half;
  for (int k = 0; k < 3; ++k) centre[k] = 0.5 * (box.min[k] + box.max[k]), half[k] = 0.5 * (box.max[k] - box.min[k]) / scale;
  EXPECT_NEAR(centre[0], 0, 1e-6);
  EXPECT_NEAR(centre[1], 0, 1e-6);
  EXPECT_NEAR(centre[2], -1.5, 1e-6);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(half[k], half[0], 1e-6) << "a cube";
    EXPECT_LE(box.min[k], frustums.min[k]);
    EXPECT_GE(box.max[k], frustums.max[k]);
  }
  // Every camera's frame corners at depth 1.5 lie in the inner cube, and one reaches its side.
  double reach = 0;
  for (const Camera& c : cams)
    for (double u : {-1.0, 1.0})
      for (double v : {-0.75, 0.75}) {
        const double x = c.c2w[3] + 1.5 * u, y = c.c2w[7] + 1.5 * v;
        EXPECT_LE(std::fabs(x - centre[0]), half[0] + 1e-6);
        EXPECT_LE(std::fabs(y - centre[1]), half[0] + 1e-6);
        reach = std::max(reach, std::fabs(x - centre[0]));
      }
  EXPECT_NEAR(reach, half[0], 1e-5);
  // Half the box would leave some frustum out.
  bool outside = false;
  for (int k = 0; k < 3; ++k)
    outside = outside || frustums.min[k] < centre[k] - half[k] * scale / 2 || frustums.max[k] > centre[k] + half[k] * scale / 2;
  EXPECT_TRUE(outside);
}

// ---- Bad files ----

TEST(DatasetLlff, BadFilesNameTheFileAndTheField) {
  TempDir dir("llff_bad");
  const fs::path p = dir.path(), file = p / "poses_bounds.npy";
  writeSmallScene(p);
  ASSERT_EQ(Dataset::load(p, split("all")).cameras.size(), 3u);
  const std::vector<Row> good = smallRows();
  auto values = [&](const std::vector<Row>& rows) {
    std::vector<double> v;
    for (const Row& r : rows) v.insert(v.end(), r.begin(), r.end());
    return v;
  };
  auto withHeader = [&](const std::string& header) {
    std::string bytes = npyBytes(values(good), {3, 17});
    const size_t end = bytes.find('\n');
    return bytes.substr(0, 8) + std::string{char(header.size() & 0xff), char(header.size() >> 8)} + header + bytes.substr(end + 1);
  };
  auto changed = [&](size_t row, size_t column, double v) {
    std::vector<Row> rows = good;
    rows[row][column] = v;
    return poseBoundsBytes(rows);
  };
  auto scaledRotation = [&] {
    std::vector<Row> rows = good;
    for (int k = 0; k < 3; ++k) rows[2][5 * k] *= 2;
    return poseBoundsBytes(rows);
  };
  auto mirrored = [&] {
    std::vector<Row> rows = good;
    for (int k = 0; k < 3; ++k) std::swap(rows[1][5 * k], rows[1][5 * k + 1]);
    return poseBoundsBytes(rows);
  };
  auto tinyFocal = [&] {  // 1e8 deep at a focal length of 1e-10 pixels: the frustum is 1e18 wide
    std::vector<Row> rows = good;
    rows[0][14] = 1e-10;
    rows[0][16] = 1e8;
    return poseBoundsBytes(rows);
  };
  const std::string valid = poseBoundsBytes(good);
  std::string version3 = valid, bigEndian = valid, int64 = valid;
  version3[6] = 3;
  bigEndian.replace(bigEndian.find("<f8"), 3, ">f8");
  int64.replace(int64.find("<f8"), 3, "<i8");
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  const struct {
    std::string name, bytes;
    std::vector<std::string> fragments;
  } cases[] = {
      {"text", "near far\n1 2\n", {"not a .npy file"}},
      {"empty", "", {"not a .npy file"}},
      {"format 3.0", version3, {"format version 3.0"}},
      {"integers", int64, {"'descr'", "'<i8'", "float64"}},
      {"big-endian", bigEndian, {"'descr'", "big-endian"}},
      {"15 columns", npyBytes(std::vector<double>(45, 1.0), {3, 15}), {"shape (3, 15) is not (N, 17)"}},
      {"one dimension", npyBytes(values(good), {51}), {"shape (51,) is not (N, 17)"}},
      {"three dimensions", npyBytes(values(good), {3, 17, 1}), {"shape (3, 17, 1) is not (N, 17)"}},
      {"no rows", npyBytes({}, {0, 17}), {"shape (0, 17) holds no photos"}},
      {"no shape", withHeader("{'descr': '<f8', 'fortran_order': False, }\n"), {"'shape' is missing"}},
      {"not a dict", withHeader("[1, 2, 3]\n"), {"not the dict numpy writes"}},
      {"shape twice", withHeader("{'descr': '<f8', 'shape': (3, 17), 'fortran_order': False, 'shape': (3, 17)}\n"),
       {"'shape' is given twice"}},
      {"negative dimension", withHeader("{'descr': '<f8', 'fortran_order': False, 'shape': (-3, 17)}\n"), {"'shape' must be a tuple"}},
      {"header past the end", valid.substr(0, 40), {"header is truncated"}},
      {"truncated data", valid.substr(0, valid.size() - 8), {"the file is truncated"}},
      {"trailing bytes", valid + "xx", {"bytes after its data"}},
      {"NaN rotation", changed(1, 7, nan), {"row 1, column 7 (R[1][2]) is not finite"}},
      {"infinite far", changed(0, 16, inf), {"row 0, column 16 (far) is not finite"}},
      {"huge translation", changed(2, 8, 1e20), {"row 2, column 8 (t[1]) value 1e+20 is beyond the range"}},
      {"zero focal", changed(0, 14, 0), {"row 0: hwf focal 0 must be positive"}},
      {"negative focal", changed(1, 14, -10), {"row 1: hwf focal -10 must be positive"}},
      {"zero height", changed(2, 4, 0), {"row 2: hwf height 0 must be a whole number"}},
      {"fractional width", changed(0, 9, 7.5), {"row 0: hwf width 7.5 must be a whole number"}},
      {"zero near", changed(1, 15, 0), {"row 1: near bound 0 must be positive"}},
      {"negative near", changed(1, 15, -1), {"row 1: near bound -1 must be positive"}},
      {"near at far", changed(2, 15, 8), {"row 2: near bound 8 is not below the far bound 8"}},
      {"scaled rotation", scaledRotation(), {"row 2: pose rotation part is not orthonormal"}},
      {"mirrored rotation", mirrored(), {"row 1: pose rotation part has determinant -1"}},
      {"photo size", changed(0, 4, 7), {"row 0: image '" + (p / "images" / "p0.png").string() + "' is 8x6 but the camera says 8x7"}},
      {"frustum beyond floats", tinyFocal(), {"frustums between the near and far bounds reach beyond 1e15"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    writeText(file, c.bytes);
    const std::string m = errorOf([&] { Dataset::load(p, split("all")); });
    EXPECT_EQ(m.rfind(file.string(), 0), 0u) << "the message begins with the file: " << m;
    for (const std::string& f : c.fragments) EXPECT_MESSAGE_HAS(m, f);
  }
  // Photos: one too many, or no images/ at all.
  writeText(file, valid);
  writePng(p / "images" / "p3.png", patternImage(8, 6, 3));
  std::string m = errorOf([&] { Dataset::load(p, split("all")); });
  EXPECT_MESSAGE_HAS(m, "'" + (p / "images").string() + "' holds 4 photos");
  EXPECT_MESSAGE_HAS(m, "'" + file.string() + "' has 3 rows");
  fs::remove_all(p / "images");
  m = errorOf([&] { Dataset::load(p, split("all")); });
  EXPECT_MESSAGE_HAS(m, file.string() + ": no images/ folder beside it");
}

TEST(DatasetLlff, TheCommandLineRefusesABadFileInOneLine) {
  TempDir dir("llff_cli");
  const fs::path p = dir.path();
  writeSmallScene(p);
  std::vector<Row> rows = smallRows();
  rows[2][15] = 9;  // near beyond far
  writeRows(p, rows);
  const CliResult r = runCli("train " + p.string() + " --steps 1 -o " + (p / "m.vknerf").string());
  EXPECT_EQ(r.code, 1) << r.output;
  const std::string line = "vknerf: error: " + (p / "poses_bounds.npy").string() + ": row 2: near bound 9 is not below the far bound 8\n";
  ASSERT_GE(r.output.size(), line.size()) << r.output;
  EXPECT_EQ(r.output.substr(r.output.size() - line.size()), line) << "the output ends with the one-line error";
  EXPECT_EQ(r.output.find("loss"), std::string::npos) << "nothing trained: " << r.output;
  EXPECT_FALSE(fs::exists(p / "m.vknerf"));
}

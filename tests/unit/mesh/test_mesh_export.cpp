// Mesh export: the PLY writer read back, Model::extractMesh on a tiny model, and
// `vknerf export mesh` with its usage errors.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "reference/mesh/marching_cubes.h"
#include "support/cli_run.h"
#include "support/gpu_test.h"
#include "support/mesh_checks.h"
#include "support/ply_reader.h"
#include "support/temp_dir.h"
#include "support/tiny_config.h"
#include "vknerf/error.h"
#include "vknerf/mesh.h"
#include "vknerf/trainer.h"

using namespace vknerf;

namespace {

using test::readPly;

TEST(Ply, RoundTripsAMesh) {
  auto grid = test::sampledGrid(9, [](double x, double y, double z) { return test::ballDensity(x, y, z, 0.6); });
  auto surface = ref::marchingCubes(grid, 1.0f);
  Mesh mesh{surface.positions, {}, surface.triangles};
  for (size_t i = 0; i < mesh.positions.size(); ++i) mesh.colors.push_back(uint8_t(i * 37));
  test::TempDir dir("ply");
  writePly(dir.file("ball.ply"), mesh);
  Mesh back = readPly(dir.file("ball.ply"));
  EXPECT_EQ(back.positions, mesh.positions);
  EXPECT_EQ(back.colors, mesh.colors);
  EXPECT_EQ(back.triangles, mesh.triangles);
}

TEST(Ply, RejectsAnIndexPastTheVertices) {
  Mesh mesh{{0, 0, 0}, {1, 2, 3}, {0, 0, 1}};
  test::TempDir dir("ply");
  EXPECT_THROW(writePly(dir.file("bad.ply"), mesh), Error);
}

class MeshExport : public test::GpuTest {};

// A tiny model trained for a couple of steps: its surface at the centre's density exists, and
// the mesh is indexed within its vertices, coloured, and inside the box asked for.
TEST_F(MeshExport, TinyModelGivesAValidColouredMesh) {
  Dataset data = Dataset::load(test::scene(), {.downscale = 10});
  Trainer trainer(test::sharedContext(), data, test::tinyVanillaConfig());
  for (int i = 0; i < 2; ++i) trainer.step();
  const Model& model = trainer.model();
  MeshSettings s;
  s.resolution = 12;
  s.box = Aabb{{-0.5f, -0.5f, -0.25f}, {0.5f, 0.5f, 0.25f}};
  auto density = model.queryField(std::vector<float>{0, 0, 0}, std::vector<float>{0, 0, 1}).density;
  ASSERT_EQ(density.size(), 1u);
  s.threshold = density[0];  // a density the field takes: usually some surface around the centre
  std::vector<std::pair<uint64_t, uint64_t>> progress;
  Mesh mesh = model.extractMesh(s, [&](uint64_t done, uint64_t total) { progress.emplace_back(done, total); });
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back(), std::make_pair(mesh.densityQueries, mesh.densityQueries));
  for (size_t i = 1; i < progress.size(); ++i) EXPECT_GT(progress[i].first, progress[i - 1].first);
  // The centre's own density is crossed somewhere in the box: the surface is not empty.
  ASSERT_FALSE(mesh.triangles.empty());
  EXPECT_EQ(mesh.colors.size(), mesh.positions.size());
  for (uint32_t i : mesh.triangles) ASSERT_LT(i, mesh.positions.size() / 3);
  for (size_t v = 0; v < mesh.positions.size(); v += 3)
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(mesh.positions[v + k], s.box->min[k] - 1e-5f);
      EXPECT_LE(mesh.positions[v + k], s.box->max[k] + 1e-5f);
    }
}

TEST_F(MeshExport, BadSettingsAreErrors) {
  Dataset data = Dataset::load(test::scene(), {.downscale = 10});
  Trainer trainer(test::sharedContext(), data, TrainConfig::vanilla(ctx()));
  EXPECT_THROW(trainer.model().extractMesh({.resolution = 1}), Error);
  EXPECT_THROW(trainer.model().extractMesh({.box = Aabb{{0, 0, 0}, {1, -1, 1}}}), Error);
  EXPECT_THROW(trainer.model().queryField(std::vector<float>{0, 0}, std::vector<float>{0, 0}), Error);
}

TEST(MeshExportCli, WritesAPlyAndRejectsBadFlags) {
  using test::runCli;
  const std::string model = test::temp("tiny.vknerf"), ply = test::temp("tiny.ply");
  ASSERT_EQ(runCli("train " + test::scene() + " --steps 2 --downscale 10 -o " + model).code, 0);
  auto r = runCli("export mesh " + model + " -o " + ply + " --resolution 10 --threshold 0.001");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("density threshold 0.001"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("faces in"), std::string::npos) << r.output;
  Mesh back = readPly(ply);
  for (uint32_t i : back.triangles) ASSERT_LT(i, back.positions.size() / 3);
  EXPECT_EQ(runCli("export mesh " + model + " -o " + ply + " --resolution 0").code, 2);
  EXPECT_EQ(runCli("export mesh " + model + " -o " + ply + " --bbox 1 0 0 0 1 1").code, 2);
  EXPECT_EQ(runCli("export mesh " + model + " -o " + ply + " --bbox 0 0 0").code, 2);
  EXPECT_EQ(runCli("export mesh " + model).code, 2);  // no -o
  EXPECT_EQ(runCli("export mesh /no/such.vknerf -o " + ply).code, 1);
}

}  // namespace

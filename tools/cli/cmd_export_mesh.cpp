// `vknerf export mesh MODEL -o mesh.ply [--resolution N] [--threshold T] [--bbox x0 y0 z0 x1 y1 z1]
// [--whole-box]`: the trained field's surface by marching cubes on the device, vertex-coloured, as
// binary PLY; the fast model's density is sampled only near its occupied cells unless --whole-box.
#include <chrono>
#include <cstdio>
#include <vector>

#include "checks.h"
#include "command_files.h"
#include "command.h"
#include "progress.h"
#include "vknerf/file_output.h"
#include "vknerf/mesh.h"
#include "vknerf/trainer.h"

namespace vknerf::cli {
namespace {

struct Options {
  std::string model, output;
  MeshSettings mesh;
  std::vector<float> bbox;
};

int run(Options o, const Globals& g) {
  if (o.mesh.resolution < 2) throw UsageError("export mesh: --resolution must be at least 2");
  if (!o.bbox.empty()) {
    Aabb box{{o.bbox[0], o.bbox[1], o.bbox[2]}, {o.bbox[3], o.bbox[4], o.bbox[5]}};
    for (int k = 0; k < 3; ++k)
      if (!(box.max[k] > box.min[k]))
        throw UsageError("export mesh: --bbox needs x0 y0 z0 below x1 y1 z1 (axis " + std::to_string(k) + " is empty)");
    o.mesh.box = box;
  }
  if (!(o.mesh.threshold > 0)) {  // a density is never negative: every point would be inside, no surface
    char got[32];
    std::snprintf(got, sizeof got, "%g", o.mesh.threshold);
    throw UsageError(std::string("export mesh: --threshold must be a positive density, got ") + got);
  }
  CommandFiles files("export mesh");
  files.input(o.model, "model").output(o.output, "-o");
  files.check();
  Model model = Model::load(g.context(), o.model);
  std::printf("density threshold %g, resolution %u\n", o.mesh.threshold, o.mesh.resolution);
  const auto start = std::chrono::steady_clock::now();
  Mesh mesh = model.extractMesh(o.mesh, progressPrinter("sampling the density"));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writePly(o.output, mesh);
  std::printf("%zu vertices, %zu faces in %.1f s; written to %s\n", mesh.positions.size() / 3, mesh.triangles.size() / 3,
              seconds, o.output.c_str());
  std::printf("density sampled at %.1f%% of the %llu grid points%s\n",
              100.0 * double(mesh.densityQueries) / double(mesh.gridSamples), (unsigned long long)mesh.gridSamples,
              mesh.densityQueries < mesh.gridSamples ? " (near the occupied cells)" : "");
  if (mesh.triangles.empty())
    std::printf("no surface at this threshold: the density stays below it everywhere (try a lower --threshold) or "
                "above it everywhere (a --bbox reaching outside the object)\n");
  return 0;
}

Registration exportMesh("export mesh", "Export the trained field's surface as a vertex-coloured PLY mesh",
                        [](CLI::App& app, const Globals& g) {
  auto o = std::make_shared<Options>();
  app.add_option("model", o->model, "Model checkpoint (from vknerf train)")->required();
  app.add_option("-o,--output", o->output, "Output PLY file")->required();
  app.add_option("--resolution", o->mesh.resolution, "Density samples along the box's longest side (default 256)");
  app.add_option("--threshold", o->mesh.threshold, "Density of the surface, positive (default " +
                 std::to_string(MeshSettings::kDefaultThreshold) + ")")->check(FiniteNumber);
  app.add_flag("--whole-box", [o](int64_t) { o->mesh.occupiedOnly = false; },
               "Sample the density over the whole box, not only near the occupancy grid's occupied cells (fast model)");
  app.add_option("--bbox", o->bbox, "Region to mesh: x0 y0 z0 x1 y1 z1 (default: the model's scene box)")
      ->expected(6)->check(FiniteNumber);
  return [o, &g] { return run(*o, g); };
});

}  // namespace
}  // namespace vknerf::cli

// `vknerf export points MODEL --scene SCENE -o points.ply [--split S] [--downscale N] [--min-opacity A]
// [--max-points N]`: every training view rendered, each pixel the field makes opaque enough placed
// at its expected depth with the field's colour there, as a binary PLY point cloud. The scene names
// the views (any split, any --downscale), checked against the model's record.
#include <chrono>
#include <cstdio>
#include <string>

#include "checks.h"
#include "command_files.h"
#include "command.h"
#include "progress.h"
#include "vknerf/checkpoint_scene.h"
#include "vknerf/dataset.h"
#include "vknerf/point_cloud.h"
#include "vknerf/trainer.h"

namespace vknerf::cli {
namespace {

struct Options {
  std::string model, scene, output, split = "train";
  uint32_t downscale = 1;
  float minOpacity = 0.5f;
  uint64_t maxPoints = 0;  // 0: all
};

// Every (size / keep)-th point, so that what is kept spreads evenly over the views.
void keepEvenly(PointCloud& cloud, uint64_t keep) {
  const uint64_t size = cloud.positions.size() / 3;
  if (keep == 0 || size <= keep) return;
  for (uint64_t j = 0; j < keep; ++j) {
    const uint64_t from = j * size / keep;
    for (int k = 0; k < 3; ++k) {
      cloud.positions[3 * j + k] = cloud.positions[3 * from + k];
      cloud.colors[3 * j + k] = cloud.colors[3 * from + k];
    }
  }
  cloud.positions.resize(3 * keep);
  cloud.colors.resize(3 * keep);
}

int run(const Options& o, const Globals& g) {
  if (!(o.minOpacity >= 0 && o.minOpacity < 1)) throw UsageError("export points: --min-opacity must be in [0, 1)");
  CommandFiles files("export points");
  files.input(o.model, "model").scene(o.scene, "--scene").output(o.output, "-o");
  files.check();
  DatasetOptions dopt;
  dopt.split = o.split;
  dopt.downscale = o.downscale;
  const Dataset data = Dataset::load(o.scene, dopt);
  checkTrainedOn(o.model, data, dopt);  // another scene's cameras would place points at random
  Model model = Model::load(g.context(), o.model);
  std::printf("%zu %s views of %s, opacity above %g\n", data.cameras.size(), o.split.c_str(), o.scene.c_str(),
              o.minOpacity);
  PointCloud cloud;
  const auto start = std::chrono::steady_clock::now();
  for (size_t i = 0; i < data.cameras.size(); ++i) {
    const size_t before = cloud.positions.size() / 3;
    const RenderedImage img =
        model.render(data.cameras[i], progressPrinter("view " + std::to_string(i) + ": pixels", true));
    appendVisiblePoints(cloud, data.cameras[i], img, o.minOpacity, model.config().background);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("view %zu/%zu: %zu points (%zu in all), %.1f s elapsed\n", i + 1, data.cameras.size(),
                cloud.positions.size() / 3 - before, cloud.positions.size() / 3, elapsed);
    std::fflush(stdout);
  }
  const size_t found = cloud.positions.size() / 3;
  keepEvenly(cloud, o.maxPoints);
  writePly(o.output, cloud);
  std::printf("%zu points", cloud.positions.size() / 3);
  if (cloud.positions.size() / 3 < found) std::printf(" (evenly kept of %zu)", found);
  std::printf(" written to %s\n", o.output.c_str());
  if (found == 0) std::printf("no pixel is that opaque: try a lower --min-opacity\n");
  return 0;
}

Registration exportPoints("export points", "Export the points the training views see as a coloured PLY point cloud",
                          [](CLI::App& app, const Globals& g) {
  auto o = std::make_shared<Options>();
  app.add_option("model", o->model, "Model checkpoint (from vknerf train)")->required();
  app.add_option("--scene", o->scene, "The scene the model was trained on: its cameras are rendered")->required();
  app.add_option("-o,--output", o->output, "Output PLY file")->required();
  app.add_option("--split", o->split, "Split of SCENE whose views to render")
      ->check(CLI::IsMember({"train", "val", "test", "all"}));
  app.add_option("--downscale", o->downscale, "Render the views this many times smaller (fewer points)")
      ->check(CLI::Range(1u, 64u));
  app.add_option("--min-opacity", o->minOpacity, "Keep pixels whose opacity exceeds this (default 0.5)")
      ->check(FiniteNumber);
  app.add_option("--max-points", o->maxPoints, "Keep at most this many points, evenly over the views (default 0: all)");
  return [o, &g] { return run(*o, g); };
});

}  // namespace
}  // namespace vknerf::cli

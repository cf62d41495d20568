// `vknerf render MODEL SCENE|--orbit N -o DIR`: RGB, depth (colour-mapped PNG and raw PFM) and
// opacity for a split's cameras or an orbit, frames numbered for assembly into a video.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "checks.h"
#include "command.h"
#include "progress.h"
#include "lib/render_output.h"
#include "vknerf/camera.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"
#include "vknerf/trainer.h"

namespace vknerf::cli {
namespace {

struct Options {
  std::string model, scene, outDir, split = "test";
  uint32_t orbit = 0, downscale = 1, size = 100, limit = 0;
  float elevationDegrees = 30, radius = 0;
};

// n cameras on a circle around the box centre, looking at it, +Z up (nerf_synthetic's world).
std::vector<Camera> orbitCameras(uint32_t n, const Aabb& box, float radius, float elevationDeg, const Camera& like) {
  const std::array<float, 3> centre{0.5f * (box.min[0] + box.max[0]), 0.5f * (box.min[1] + box.max[1]),
                                    0.5f * (box.min[2] + box.max[2])};
  std::vector<Camera> cams;
  for (uint32_t i = 0; i < n; ++i) {
    Camera cam = like;
    cam.c2w = orbitPose(centre, radius, elevationDeg, i, n);
    cams.push_back(cam);
  }
  return cams;
}

int run(const Options& o, const Globals& g) {
  if (o.scene.empty() && o.orbit == 0) {
    std::fprintf(stderr, "vknerf render: give a SCENE (renders its --split cameras) or --orbit N\n");
    return 2;
  }
  // The output folder before any rendering: a path that cannot hold the frames fails now.
  std::error_code ec;
  std::filesystem::create_directories(o.outDir, ec);
  if (!std::filesystem::is_directory(o.outDir))
    throw Error("output folder " + o.outDir + ": " + (ec ? ec.message() : "exists and is not a folder"));
  checkOutputPath(o.outDir + "/rgb_0000.png", "output folder " + o.outDir);
  auto ctx = g.context();
  Model model = Model::load(ctx, o.model);
  std::vector<Camera> cams;
  Camera like = pinholeFromFocal(o.size, o.size, 1.2f * float(o.size));  // ~45 degree field of view
  float radius = o.radius;
  if (!o.scene.empty()) {
    DatasetOptions dopt;
    dopt.split = o.split;
    dopt.downscale = o.downscale;
    Dataset data = Dataset::load(o.scene, dopt);
    cams = data.cameras;
    like = data.cameras[0];
    if (radius <= 0) {
      for (auto& c : data.cameras) radius += std::sqrt(c.c2w[3] * c.c2w[3] + c.c2w[7] * c.c2w[7] + c.c2w[11] * c.c2w[11]);
      radius /= float(data.cameras.size());
    }
  }
  if (radius <= 0) radius = 4.0f;
  if (o.orbit) cams = orbitCameras(o.orbit, model.bounds(), radius, o.elevationDegrees, like);
  if (o.limit && cams.size() > o.limit) cams.resize(o.limit);
  const auto& b = model.bounds();
  float diag = std::sqrt((b.max[0] - b.min[0]) * (b.max[0] - b.min[0]) + (b.max[1] - b.min[1]) * (b.max[1] - b.min[1]) +
                         (b.max[2] - b.min[2]) * (b.max[2] - b.min[2]));
  for (size_t i = 0; i < cams.size(); ++i) {
    auto t0 = std::chrono::steady_clock::now();
    RenderedImage img = model.render(cams[i], progressPrinter("rendering view " + std::to_string(i) + ": pixels", true));
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    char name[64];
    std::snprintf(name, sizeof name, "%04zu", i);
    std::string base = o.outDir + "/";
    nerf::saveRgbPng(base + "rgb_" + name + ".png", img);
    nerf::saveDepthPng(base + "depth_" + name + ".png", img, std::max(radius - 0.5f * diag, 0.0f), radius + 0.5f * diag);
    nerf::saveDepthPfm(base + "depth_" + name + ".pfm", img);
    nerf::saveOpacityPng(base + "opacity_" + name + ".png", img);
    std::printf("frame %s: %ux%u in %.3f s -> %srgb_%s.png\n", name, img.width, img.height, s, base.c_str(), name);
  }
  return 0;
}

Registration render("render", "Render RGB, depth and opacity images from a trained model", [](CLI::App& app, const Globals& g) {
  auto o = std::make_shared<Options>();
  app.add_option("model", o->model, "Model checkpoint (from vknerf train)")->required();
  app.add_option("scene", o->scene, "Scene whose cameras to render (see --split)");
  app.add_option("-o,--output", o->outDir, "Output folder")->required();
  app.add_option("--split", o->split, "Split of SCENE to render")->check(CLI::IsMember({"train", "val", "test", "all"}));
  app.add_option("--orbit", o->orbit, "Render N views on a circle around the scene instead")->check(CLI::Range(1u, 10000u));
  app.add_option("--elevation", o->elevationDegrees, "Orbit elevation in degrees")->check(FiniteNumber);
  app.add_option("--radius", o->radius, "Orbit radius (default: the scene cameras' mean distance, else 4)")->check(FiniteNumber);
  app.add_option("--size", o->size, "Orbit image size without a SCENE")->check(CLI::Range(1u, 8192u));
  app.add_option("--downscale", o->downscale, "Downscale SCENE's images by this factor")->check(CLI::Range(1u, 64u));
  app.add_option("--limit", o->limit, "Render at most this many views");
  return [o, &g] { return run(*o, g); };
});

}  // namespace
}  // namespace vknerf::cli

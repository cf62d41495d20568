// `vknerf eval MODEL SCENE`: PSNR and SSIM on held-out views, as JSON and CSV.
#include <chrono>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "checks.h"
#include "command_files.h"
#include "command.h"
#include "progress.h"
#include "io/image_io.h"
#include "lib/csv.h"
#include "lib/metrics.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"
#include "vknerf/trainer.h"

namespace vknerf::cli {
namespace {

struct Options {
  std::string model, scene, split = "test", json, csv;
  uint32_t downscale = 1, limit = 0;
};


int run(const Options& o, const Globals& g) {
  // Before the evaluation: a report that cannot be written, or would replace an input, would lose it.
  CommandFiles files("eval");
  files.input(o.model, "model").scene(o.scene).output(o.json, "--json").output(o.csv, "--csv");
  files.check();
  auto ctx = g.context();
  Model model = Model::load(ctx, o.model);
  DatasetOptions dopt;
  dopt.split = o.split;
  dopt.downscale = o.downscale;
  dopt.progress = progressPrinter("decoding images");
  Dataset data = Dataset::load(o.scene, dopt);
  size_t n = data.cameras.size();
  if (o.limit && n > o.limit) n = o.limit;
  nlohmann::json images = nlohmann::json::array();
  double sumPsnr = 0, sumSsim = 0, sumSeconds = 0;
  for (size_t i = 0; i < n; ++i) {
    auto t0 = std::chrono::steady_clock::now();
    RenderedImage img = model.render(data.cameras[i], progressPrinter("rendering " + data.names[i] + ": pixels", true));
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    auto gt = nerf::compositeOver(data.images[i], model.config().background);
    double p = nerf::psnr(img.rgb, gt), q = nerf::ssim(img.rgb, gt, img.width, img.height);
    sumPsnr += p, sumSsim += q, sumSeconds += s;
    images.push_back({{"name", data.names[i]}, {"psnr", p}, {"ssim", q}, {"seconds", s}});
    std::printf("%-40s PSNR %6.2f dB  SSIM %.4f  %.3f s\n", data.names[i].c_str(), p, q, s);
  }
  nlohmann::json result = {{"model", o.model}, {"scene", o.scene}, {"split", o.split}, {"count", n},
                           {"psnr", sumPsnr / double(n)}, {"ssim", sumSsim / double(n)},
                           {"seconds_per_image", sumSeconds / double(n)}, {"device", ctx->describe()}, {"images", images}};
  std::printf("mean over %zu %s views: PSNR %.2f dB, SSIM %.4f, %.3f s per image\n", n, o.split.c_str(),
              sumPsnr / double(n), sumSsim / double(n), sumSeconds / double(n));
  if (!o.json.empty()) writeFileAtomically(o.json, result.dump(2) + "\n");
  if (!o.csv.empty()) {
    std::ostringstream f;
    f << "name,psnr,ssim,seconds\n";
    for (auto& im : images)
      f << nerf::csvField(im["name"].get<std::string>()) << "," << im["psnr"] << "," << im["ssim"] << "," << im["seconds"] << "\n";
    writeFileAtomically(o.csv, f.str());
  }
  return 0;
}

Registration eval("eval", "Measure PSNR and SSIM of a model on a scene's held-out views", [](CLI::App& app, const Globals& g) {
  auto o = std::make_shared<Options>();
  app.add_option("model", o->model, "Model checkpoint")->required();
  app.add_option("scene", o->scene, "Scene folder or transforms JSON")->required();
  app.add_option("--split", o->split, "Split to evaluate")->check(CLI::IsMember({"train", "val", "test", "all"}));
  app.add_option("--json", o->json, "Write the results as JSON");
  app.add_option("--csv", o->csv, "Write per-image results as CSV");
  app.add_option("--downscale", o->downscale, "Downscale images by this factor")->check(CLI::Range(1u, 64u));
  app.add_option("--limit", o->limit, "Evaluate at most this many views (default 0: all)");
  return [o, &g] { return run(*o, g); };
});

}  // namespace
}  // namespace vknerf::cli

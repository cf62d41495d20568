// `vknerf bench train SCENE`: speed against error. Trains each configuration for the same wall-clock
// budget, measuring held-out PSNR/SSIM at regular points of training time (evaluation is not
// counted), then times rendering against PSNR for a few sample budgets. Writes train.csv,
// render.csv and bench.md into --out; tools/dev/plot_bench.py draws them.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "checks.h"
#include "command_files.h"
#include "command.h"
#include "vknerf/image_io.h"
#include "lib/csv.h"
#include "lib/metrics.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"
#include "vknerf/trainer.h"

namespace vknerf::cli {
namespace {

struct Options {
  std::string scene, out = "bench-out";
  // Both, to compare: fast (what `vknerf train` trains by default) first, then the NeRF paper's
  // model as the baseline it is measured against (docs/performance.md's table comes from this).
  std::vector<std::string> configs{"fast", "vanilla"};
  double seconds = 120;
  uint32_t points = 6, evalViews = 3, finalViews = 0, renderViews = 5, seed = 0;
  std::vector<std::string> vanillaBudgets{"16+32", "32+64", "64+128"};
  std::vector<uint32_t> fastBudgets{128, 256, 512};
};

struct Score {
  double psnr = 0, ssim = 0, secondsPerImage = 0;
};

template <class RenderFn>
Score evaluate(RenderFn&& render, const Dataset& test, size_t views, const std::array<float, 3>& background) {
  Score s;
  const size_t n = views ? std::min(views, test.cameras.size()) : test.cameras.size();
  for (size_t i = 0; i < n; ++i) {
    auto t0 = std::chrono::steady_clock::now();
    RenderedImage img = render(test.cameras[i]);
    s.secondsPerImage += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    auto gt = vknerf::compositeOver(test.images[i], background);
    s.psnr += nerf::psnr(img.rgb, gt);
    s.ssim += nerf::ssim(img.rgb, gt, img.width, img.height);
  }
  s.psnr /= double(n), s.ssim /= double(n), s.secondsPerImage /= double(n);
  return s;
}

struct TrainRow {
  std::string config;
  double seconds;
  uint32_t steps;
  Score score;
  double stepsPerSecond, raysPerSecond, samplesPerSecond;
};

struct RenderRow {
  std::string config, budget;
  Score score;
};

RenderSettings parseBudget(const std::string& config, const std::string& text) {
  RenderSettings r;
  if (config == "fast") {
    r.marchSteps = uint32_t(std::stoul(text));
  } else {
    auto plus = text.find('+');
    if (plus == std::string::npos) throw Error("render budget \"" + text + "\": expected COARSE+FINE, e.g. 32+64");
    r.coarseSamples = uint32_t(std::stoul(text.substr(0, plus)));
    r.fineSamples = uint32_t(std::stoul(text.substr(plus + 1)));
  }
  return r;
}

int run(const Options& o, const Globals& g) {
  CommandFiles files("bench train");
  files.scene(o.scene).outputFolder(o.out, "-o");
  files.check();
  auto ctx = g.context();
  Dataset train = Dataset::load(o.scene, {.split = "train"});
  Dataset test = Dataset::load(o.scene, {.split = "test"});
  files.createFolders();
  std::vector<TrainRow> rows;
  std::vector<RenderRow> renders;
  std::vector<std::string> described, statistics;
  for (const std::string& name : o.configs) {
    TrainConfig cfg = TrainConfig::named(name, *ctx);
    cfg.seed = o.seed;
    described.push_back(cfg.describe());
    std::printf("== %s\n", cfg.describe().c_str());
    {
      // One untimed step on a throwaway trainer first: the first use of each kernel compiles its
      // pipeline (lavapipe JIT, ~1 min for vanilla with a cold Mesa shader cache), a one-off cost
      // that would otherwise sit in the first point of the curve. Reported, not counted.
      auto t0 = std::chrono::steady_clock::now();
      Trainer warm(ctx, train, cfg);
      warm.step(false);
      warm.model().render(test.cameras[0]);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("%-8s warm-up (pipeline compilation, first step and render; not counted): %.1f s\n", name.c_str(), s);
      char line[160];
      std::snprintf(line, sizeof line, "- %s: warm-up (pipeline compilation, first step and render; not counted) %.1f s",
                    name.c_str(), s);
      statistics.push_back(line);
    }
    Trainer trainer(ctx, train, cfg);
    double trained = 0;  // seconds spent in training steps only
    uint64_t rays = 0, samples = 0;
    uint32_t lastSteps = 0;
    double lastSeconds = 0;
    uint64_t lastRays = 0, lastSamples = 0;
    for (uint32_t p = 1; p <= o.points; ++p) {
      const double until = o.seconds * p / o.points;
      auto t0 = std::chrono::steady_clock::now();
      auto now = [&] { return trained + std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
      // The rates decay over the whole budget, as `vknerf train --time` decays them; the earlier
      // points see them mid-decay.
      for (double t = trained; t < until; t = now()) {
        trainer.setRunProgress(t / o.seconds);
        if (auto done = trainer.submitStep(false)) rays += done->rays, samples += done->samples;
      }
      if (auto done = trainer.finishSteps()) rays += done->rays, samples += done->samples;
      trained = now();
      const bool last = p == o.points;
      if (trainer.steps() == lastSteps && !last) continue;  // one slow step spanned this point
      Score s = evaluate([&](const Camera& c) { return trainer.model().render(c); }, test,
                         last ? o.finalViews : o.evalViews, cfg.background);
      const double dt = trained - lastSeconds;
      rows.push_back({name, trained, trainer.steps(), s, (trainer.steps() - lastSteps) / dt,
                      double(rays - lastRays) / dt, double(samples - lastSamples) / dt});
      std::printf("%-8s %7.1f s  %6u steps  PSNR %6.2f dB  SSIM %.4f  %6.2f steps/s  %8.0f rays/s  %9.0f samples/s\n",
                  name.c_str(), trained, trainer.steps(), s.psnr, s.ssim, rows.back().stepsPerSecond,
                  rows.back().raysPerSecond, rows.back().samplesPerSecond);
      lastSteps = trainer.steps(), lastSeconds = trained, lastRays = rays, lastSamples = samples;
    }
    std::ostringstream stats;
    stats << "- " << name << " after " << trainer.steps() << " steps:";
    for (auto& [key, value] : statisticsRows(trainer.statistics())) {
      std::printf("  %-48s %g\n", key.c_str(), value);
      stats << "\n  - " << key << ": " << value;
    }
    statistics.push_back(stats.str());
    const std::string ckpt = (std::filesystem::path(o.out) / (name + ".vknerf")).string();
    trainer.save(ckpt);
    std::vector<std::string> budgets = o.vanillaBudgets;
    if (name == "fast") {
      budgets.clear();
      for (uint32_t b : o.fastBudgets) budgets.push_back(std::to_string(b));
    }
    for (const std::string& b : budgets) {
      Model m = Model::load(ctx, ckpt, parseBudget(name, b));
      m.render(test.cameras[0]);  // first use pays one-off costs; time the steady state
      Score s = evaluate([&](const Camera& c) { return m.render(c); }, test, o.renderViews, cfg.background);
      renders.push_back({name, b, s});
      std::printf("%-8s render %-8s %.3f s/frame  PSNR %6.2f dB  SSIM %.4f\n", name.c_str(), b.c_str(),
                  s.secondsPerImage, s.psnr, s.ssim);
    }
  }

  const auto dir = std::filesystem::path(o.out);
  {
    std::ostringstream f;
    f << "config,seconds,steps,psnr,ssim,steps_per_s,rays_per_s,samples_per_s\n";
    for (auto& r : rows)
      f << nerf::csvField(r.config) << "," << r.seconds << "," << r.steps << "," << r.score.psnr << "," << r.score.ssim
        << "," << r.stepsPerSecond << "," << r.raysPerSecond << "," << r.samplesPerSecond << "\n";
    writeFileAtomically((dir / "train.csv").string(), f.str());
  }
  {
    std::ostringstream f;
    f << "config,budget,seconds_per_frame,psnr,ssim\n";
    for (auto& r : renders)
      f << nerf::csvField(r.config) << "," << nerf::csvField(r.budget) << "," << r.score.secondsPerImage << ","
        << r.score.psnr << "," << r.score.ssim << "\n";
    writeFileAtomically((dir / "render.csv").string(), f.str());
  }
  std::ostringstream md;
  char line[512];
  md << "Device: " << ctx->describe() << "  \nScene: `" << o.scene << "`, " << train.cameras.size() << " training and "
     << test.cameras.size() << " test views of " << test.cameras[0].width << "x" << test.cameras[0].height
     << "; budget " << o.seconds << " s of training per configuration (evaluation not counted); intermediate points on "
     << o.evalViews << " test views, the last on " << (o.finalViews ? o.finalViews : test.cameras.size())
     << "; render budgets on " << (o.renderViews ? o.renderViews : test.cameras.size()) << ".\n\n";
  for (size_t i = 0; i < o.configs.size(); ++i) md << "- " << described[i] << "\n";
  md << "\n| config | train s | steps | PSNR dB | SSIM | steps/s | rays/s | samples/s |\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (auto& r : rows) {
    std::snprintf(line, sizeof line, "| %s | %.1f | %u | %.2f | %.3f | %.2f | %.0f | %.0f |\n", r.config.c_str(),
                  r.seconds, r.steps, r.score.psnr, r.score.ssim, r.stepsPerSecond, r.raysPerSecond,
                  r.samplesPerSecond);
    md << line;
  }
  md << "\n";
  for (auto& s : statistics) md << s << "\n";
  md << "\n| config | render budget | s/frame | PSNR dB | SSIM |\n|---|---|---:|---:|---:|\n";
  for (auto& r : renders) {
    std::snprintf(line, sizeof line, "| %s | %s | %.3f | %.2f | %.3f |\n", r.config.c_str(),
                  (r.config == "fast" ? r.budget + " steps/diagonal" : r.budget + " samples").c_str(),
                  r.score.secondsPerImage, r.score.psnr, r.score.ssim);
    md << line;
  }
  writeFileAtomically((dir / "bench.md").string(), md.str());
  std::printf("\n%s\nwrote %s/{train.csv,render.csv,bench.md}; plot with: python3 tools/dev/plot_bench.py %s\n",
              md.str().c_str(), o.out.c_str(), o.out.c_str());
  return 0;
}

Registration benchTrain(
    "bench train", "Speed against error: held-out PSNR over training time, and render time against PSNR, per configuration",
    [](CLI::App& app, const Globals& g) {
      auto o = std::make_shared<Options>();
      app.add_option("scene", o->scene, "Scene folder or transforms JSON (train and test splits)")->required();
      app.add_option("--config", o->configs, "Configurations to compare, in this order (default: fast vanilla)")
          ->check(CLI::IsMember({"fast", "vanilla"}));
      app.add_option("--time", o->seconds, "Training budget per configuration, seconds")->check(PositiveFinite);
      app.add_option("--points", o->points, "Evaluation points over the budget")->check(CLI::Range(1u, 1000u));
      app.add_option("--eval-views", o->evalViews, "Test views at intermediate points")->check(CLI::Range(1u, 100000u));
      app.add_option("--final-views", o->finalViews, "Test views at the last point and for rendering (0: all)");
      app.add_option("--render-views", o->renderViews, "Test views per render budget (0: all)");
      app.add_option("--vanilla-budgets", o->vanillaBudgets, "Render sample budgets COARSE+FINE for vanilla");
      app.add_option("--fast-budgets", o->fastBudgets, "Render march steps per box diagonal for fast");
      app.add_option("--seed", o->seed, "Random seed");
      app.add_option("-o,--out", o->out, "Output folder");
      return [o, &g] { return run(*o, g); };
    });

}  // namespace
}  // namespace vknerf::cli

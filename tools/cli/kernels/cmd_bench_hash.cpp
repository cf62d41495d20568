// `vknerf bench hash`: the hash encoding's backward pass (HashEncoding::recordBackward) with each
// HashBackwardMode on the same points, dFeatures and table in one run: uniform random points and
// ray-ordered points (consecutive samples along a segment, as the marcher emits them, so neighbours
// share coarse cells), for the fast model's grid (L=8 F=2 T=15) and the default one (L=16 F=2 T=19).
// Times are host wall time of submitAndWait for one recorded command buffer, best of --repeats
// after a warm-up submission (shader JIT); SortReduce's stages from GPU timestamps of one more run.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "command.h"
#include "gpu/memory/buffer.h"
#include "gpu/dispatch/recorder.h"
#include "models/fast/fast_field.h"  // hashGridConfigFor
#include "nerf/encoding/hash_encoding.h"
#include "nerf/network/gradient_paths.h"
#include "vknerf/config.h"

namespace vknerf::cli {
namespace {

struct Options {
  uint32_t samples = 1u << 18, repeats = 5, samplesPerRay = 64;
  bool breakdown = true, wide = false;
};

std::vector<float> uniformPoints(uint32_t n, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> v(4 * size_t(n), 0.0f);
  for (uint32_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) v[4 * size_t(i) + a] = u(gen);
  return v;
}

// Rays of `perRay` evenly spaced samples between two uniform points of the box.
std::vector<float> rayPoints(uint32_t n, uint32_t perRay, uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> v(4 * size_t(n), 0.0f);
  float a[3] = {}, b[3] = {};
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t k = i % perRay;
    if (k == 0)
      for (int j = 0; j < 3; ++j) a[j] = u(gen), b[j] = u(gen);
    const float t = (float(k) + 0.5f) / float(perRay);
    for (int j = 0; j < 3; ++j) v[4 * size_t(i) + j] = a[j] + t * (b[j] - a[j]);
  }
  return v;
}

const char* modeName(nerf::HashBackwardMode m) {
  switch (m) {
    case nerf::HashBackwardMode::Atomic: return "Atomic";
    case nerf::HashBackwardMode::SubgroupMerged: return "SubgroupMerged";
    case nerf::HashBackwardMode::SortReduce: return "SortReduce";
    case nerf::HashBackwardMode::CompareSwap: return "CompareSwap";
  }
  return "?";
}

int run(const Options& o, Context& ctx) {
  using nerf::HashBackwardMode;
  struct Grid {
    std::string name;
    nerf::HashGridConfig config;
  };
  // The fast model's grid as TrainConfig::fast and the Trainer size it for the sample scene on this
  // device (L=8 F=2 T=15, finest 256 on a CPU; the table and finest resolution follow the dataset).
  FastModel sample = TrainConfig::fast(ctx).fastModel();
  sample.hashLog2Size = 15;
  sample.hashGrowth = float(std::pow(256.0 / sample.hashBaseResolution, 1.0 / (sample.hashLevels - 1)));
  const nerf::HashGridConfig fastGrid = models::hashGridConfigFor(sample);
  auto label = [](const nerf::HashGridConfig& c, const char* what) {
    return "L=" + std::to_string(c.levels) + " F=" + std::to_string(c.featuresPerLevel) +
           " T=" + std::to_string(c.log2TableSize) + what;
  };
  std::vector<Grid> grids = {{label(fastGrid, " (fast)"), fastGrid}, {"L=16 F=2 T=19", {16, 2, 19, 16, double(1.447f)}}};
  // Atomic's float atomics grow with F, SortReduce's two uint atomics per contribution do not.
  if (o.wide) {
    nerf::HashGridConfig wide = fastGrid;
    wide.featuresPerLevel = 8;
    grids.push_back({label(wide, ""), wide});
  }
  // Only the modes the device can run (nerf/network/gradient_paths.h).
  const nerf::GradientPaths paths = nerf::gradientPathsFor(ctx);
  std::vector<HashBackwardMode> modes{HashBackwardMode::CompareSwap, HashBackwardMode::SortReduce};
  if (paths.hash == HashBackwardMode::Atomic) modes.insert(modes.begin(), HashBackwardMode::Atomic);
  if (paths.hashSubgroupMerge) modes.insert(modes.begin() + 1, HashBackwardMode::SubgroupMerged);
  if (modes.size() == 2) std::printf("device without float atomics: CompareSwap and SortReduce only\n");
  const uint32_t n = o.samples;
  std::printf("hash encoding backward, %u samples, best of %u (us per sample; ratio = time / Atomic's)\n", n, o.repeats);
  std::printf("%-20s %-9s %-15s %10s %10s %8s\n", "grid", "points", "mode", "ms", "us/sample", "ratio");
  for (const Grid& grid : grids) {
    const uint32_t stride = (grid.config.levels * grid.config.featuresPerLevel + 3) / 4 * 4;
    std::vector<float> dF(size_t(n) * stride);
    std::mt19937 gen(7);
    std::uniform_real_distribution<float> u(-1, 1);
    for (auto& x : dF) x = u(gen);
    auto db = gpu::Buffer::of(ctx, dF);
    gpu::Buffer grads(ctx, core::hashGridParameterCount(grid.config) * 4);
    grads.zero();
    for (const char* points : {"uniform", "rays"}) {
      auto pb = gpu::Buffer::of(ctx, std::string(points) == "uniform" ? uniformPoints(n, 1) : rayPoints(n, o.samplesPerRay, 1));
      double atomicMs = 0;
      for (HashBackwardMode mode : modes) {
        nerf::HashEncoding enc(ctx, grid.config, mode);
        gpu::Recorder rec(ctx);
        rec.begin();
        enc.recordBackward(rec, {n, pb, db, stride, 0}, grads);
        rec.end();
        rec.submitAndWait();  // warm-up: pipelines compile at first dispatch
        double best = 1e30;
        for (uint32_t r = 0; r < o.repeats; ++r) {
          auto t0 = std::chrono::steady_clock::now();
          rec.submitAndWait();
          best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
        if (mode == HashBackwardMode::Atomic) atomicMs = best;
        std::printf("%-20s %-9s %-15s %10.1f %10.3f %8s\n", grid.name.c_str(), points, modeName(mode), best, best * 1e3 / n,
                    atomicMs > 0 ? (std::to_string(best / atomicMs).substr(0, 4) + "x").c_str() : "-");
        if (o.breakdown && mode == HashBackwardMode::SortReduce) {
          gpu::Recorder timed(ctx, true, 1024);
          timed.begin();
          enc.recordBackward(timed, {n, pb, db, stride, 0}, grads);
          timed.end();
          timed.submitAndWait();
          std::map<std::string, double> stages;
          for (auto& [label, ms] : timed.timings()) stages[label] += ms;
          std::printf("    SortReduce stages (ms, one timed run):");
          for (auto& [label, ms] : stages) std::printf(" %s %.1f", label.c_str(), ms);
          std::printf("\n");
        }
        std::fflush(stdout);
      }
    }
  }
  return 0;
}

Registration bench("bench hash", "Time the hash encoding's backward pass: float atomics against sort-and-reduce",
                   [](CLI::App& app, const Globals& g) {
                     auto o = std::make_shared<Options>();
                     app.add_option("--samples", o->samples, "Samples per batch")->check(CLI::Range(64u, 1u << 22));
                     app.add_option("--repeats", o->repeats, "Timed repetitions (best is reported)")
                         ->check(CLI::Range(1u, 100u));
                     app.add_option("--samples-per-ray", o->samplesPerRay, "Samples per ray of the ray-ordered points")
                         ->check(CLI::Range(1u, 4096u));
                     app.add_flag("!--no-breakdown", o->breakdown, "Skip SortReduce's per-stage timing");
                     app.add_flag("--wide", o->wide, "Also time an L=8 F=8 T=15 grid (more features per entry)");
                     return [o, &g] { return run(*o, *g.context()); };
                   });

}  // namespace
}  // namespace vknerf::cli

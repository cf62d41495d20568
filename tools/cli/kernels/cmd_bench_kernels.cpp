// `vknerf bench kernels`: device time of each rendering-pipeline kernel on a training-sized batch
// (median over repetitions of one command buffer, from GPU timestamps).
#include <algorithm>
#include <cstdio>
#include <map>

#include <nlohmann/json.hpp>

#include "command.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/render/composite.h"
#include "nerf/encoding/frequency_encoding.h"
#include "nerf/loss/background_colors.h"
#include "nerf/loss/photometric_loss.h"
#include "nerf/optim/adam.h"
#include "nerf/sampling/points.h"
#include "nerf/rays/rays.h"
#include "nerf/sampling/samplers.h"

namespace vknerf::cli {
namespace {

struct Options {
  uint32_t rays = 4096, coarse = 64, fine = 128, repeats = 5, params = 1 << 20;
  bool json = false;
};

int run(const Options& o, Context& ctx) {
  using namespace nerf;
  const uint32_t R = o.rays, nAll = o.coarse + o.fine, n = R * nAll;
  // A ring of cameras around the unit box, with random pixels: a realistic mix of hits and misses.
  std::vector<Camera> cams;
  for (int i = 0; i < 8; ++i) {
    float a = float(i) * 0.785398f, c = std::cos(a), s = std::sin(a);
    Camera cam;
    cam.width = cam.height = 100;
    cam.fx = cam.fy = 120;
    cam.cx = cam.cy = 50;
    cam.c2w = {-s, 0, c, 4 * c, c, 0, s, 4 * s, 0, 1, 0, 0, 0, 0, 0, 1};
    cams.push_back(cam);
  }
  auto camBuf = gpu::Buffer::of(ctx, packCameras(cams));
  std::vector<uint8_t> pixels(size_t(100) * 100 * 4 * cams.size(), 128);
  auto images = gpu::Buffer::of(ctx, pixels);
  gpu::Buffer rays(ctx, R * kRayBytes), ids(ctx, R * kPixelIdBytes), bg(ctx, R * 16);
  gpu::Buffer coarse(ctx, VkDeviceSize(R) * o.coarse * kSampleBytes), fine(ctx, VkDeviceSize(n) * kSampleBytes);
  gpu::Buffer pos(ctx, VkDeviceSize(n) * kPointBytes), dir(ctx, VkDeviceSize(n) * kPointBytes);
  gpu::Buffer posFeat(ctx, VkDeviceSize(n) * 64 * 4), dirFeat(ctx, VkDeviceSize(n) * 28 * 4);
  std::vector<float> fieldInit(size_t(n) * 4);
  for (size_t i = 0; i < fieldInit.size(); ++i) fieldInit[i] = (i % 4 == 3) ? float(i % 7) : 0.5f;
  auto field = gpu::Buffer::of(ctx, fieldInit);
  gpu::Buffer weights(ctx, VkDeviceSize(n) * 4), color(ctx, R * 16), depth(ctx, R * 4), dColor(ctx, R * 16);
  gpu::Buffer dDepth(ctx, R * 4), dField(ctx, VkDeviceSize(n) * kFieldBytes), noOffsets(ctx, 16);
  gpu::Buffer partials(ctx, 4 * ((R + 127) / 128));
  gpu::Buffer params(ctx, VkDeviceSize(o.params) * 4), grads(ctx, VkDeviceSize(o.params) * 4);
  gpu::Buffer m(ctx, VkDeviceSize(o.params) * 4), v(ctx, VkDeviceSize(o.params) * 4);
  dDepth.zero(), m.zero(), v.zero(), params.zero(), grads.zero();

  RayGeneration rayGen(ctx);
  StratifiedSampler stratified(ctx);
  PdfSampler pdf(ctx);
  SamplePoints points(ctx);
  FrequencyEncoding posEnc(ctx, 3, 10, true), dirEnc(ctx, 3, 4, true);
  Compositor compositor(ctx);
  BackgroundColors backgrounds(ctx);
  PhotometricLoss loss(ctx);
  Adam adam(ctx, AdamConfig{});

  std::map<std::string, std::vector<double>> times;
  gpu::Recorder rec(ctx, true);
  for (uint32_t rep = 0; rep <= o.repeats; ++rep) {
    rec.begin();
    rayGen.recordRandom(rec, camBuf, {uint32_t(cams.size()), rep, R}, {Aabb{}, 0.05f}, {rays, ids});
    backgrounds.recordRandom(rec, bg, R, rep);
    stratified.record(rec, {rays, R}, o.coarse, {rep, true}, coarse);
    gpu::BufferRange bgr(bg);
    compositor.recordForward(rec, {R, o.coarse, noOffsets, coarse, field, {1, 1, 1}, bgr}, {color, depth, weights});
    pdf.record(rec, {rays, R}, {coarse, weights, o.coarse}, {o.fine, {rep + 1, true}, 1e-5f}, fine);
    points.record(rec, {rays, R}, fine, nAll, Aabb{}, {pos, dir});
    posEnc.recordForward(rec, {n, pos, posFeat, 64, 0});
    dirEnc.recordForward(rec, {n, dir, dirFeat, 28, 0});
    compositor.recordForward(rec, {R, nAll, noOffsets, fine, field, {1, 1, 1}, bgr}, {color, depth, weights});
    loss.record(rec, {R, color, ids, bg}, images, camBuf, {dColor, partials});
    compositor.recordBackward(rec, {R, nAll, noOffsets, fine, field, {1, 1, 1}, bgr}, {dColor, dDepth, dField});
    adam.record(rec, {o.params, params, grads, m, v}, rep + 1, 1e-3f);
    rec.end();
    rec.submitAndWait();
    if (rep == 0) continue;  // the first run includes pipeline compilation
    auto t = rec.timings();
    std::map<std::string, int> seen;
    for (auto& [name, ms] : t) {
      int k = seen[name]++;
      times[k ? name + " #" + std::to_string(k + 1) : name].push_back(ms);
    }
  }
  nlohmann::json out = nlohmann::json::array();
  double total = 0;
  if (!o.json)
    std::printf("%u rays x (%u + %u) samples, %u Adam parameters, median of %u runs\n%-26s %10s %12s\n", R, o.coarse,
                o.fine, o.params, o.repeats, "kernel (in order of name)", "ms", "ns per ray");
  for (auto& [name, ts] : times) {
    std::sort(ts.begin(), ts.end());
    double med = ts[ts.size() / 2];
    total += med;
    if (o.json)
      out.push_back({{"kernel", name}, {"ms", med}, {"ns_per_ray", med * 1e6 / R}});
    else
      std::printf("%-26s %10.3f %12.1f\n", name.c_str(), med, med * 1e6 / R);
  }
  if (!o.json) std::printf("%-26s %10.3f %12.1f\n", "total (without the MLP)", total, total * 1e6 / R);
  if (o.json) std::printf("%s\n", out.dump(2).c_str());
  return 0;
}

Registration bench("bench kernels", "Time each rendering-pipeline kernel on a training-sized batch",
                   [](CLI::App& app, const Globals& g) {
                     auto o = std::make_shared<Options>();
                     app.add_option("--rays", o->rays, "Rays per batch")->check(CLI::Range(1u, 1u << 20));
                     app.add_option("--coarse", o->coarse, "Stratified samples per ray")->check(CLI::Range(1u, 1024u));
                     app.add_option("--fine", o->fine, "Importance samples per ray")->check(CLI::Range(0u, 1024u));
                     app.add_option("--repeats", o->repeats, "Timed repetitions")->check(CLI::Range(1u, 1000u));
                     app.add_flag("--json", o->json, "Print JSON");
                     return [o, &g] { return run(*o, *g.context()); };
                   });

}  // namespace
}  // namespace vknerf::cli

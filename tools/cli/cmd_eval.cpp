// `vknerf eval MODEL SCENE`: PSNR and SSIM on held-out views, as JSON and CSV, and with --sheet a
// contact sheet of the views (ground truth | render | depth | error).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "render_options.h"
#include "checks.h"
#include "command_files.h"
#include "command.h"
#include "progress.h"
#include "render_profile_report.h"
#include "vknerf/image_io.h"
#include "lib/contact_sheet.h"
#include "lib/csv.h"
#include "lib/metrics.h"
#include "lib/render_output.h"
#include "lib/trained_poses.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"
#include "vknerf/trainer.h"

namespace vknerf::cli {
namespace {

struct Options {
  std::string model, scene, split = "test", json, csv, sheet;
  uint32_t downscale = 1, limit = 0, sheetViews = 8, sheetSize = 100;
  RenderSettings settings;  // --appearance, --min-transmittance, --proposal-samples, --profile
  GivenRenderFlags given;
};

// The error tiles' full scale: a mean |render - truth| of 0.25 over RGB (PSNR ~12 dB on its own) and
// above is yellow. Fixed, so that sheets of two builds or scenes compare by eye.
constexpr float kSheetErrorScale = 0.25f;

// Which of n views the sheet shows: `wanted` (0: all) spread evenly from the first to the last.
std::vector<bool> sheetViews(size_t n, uint32_t wanted) {
  std::vector<bool> chosen(n, false);
  const size_t m = wanted == 0 ? n : std::min<size_t>(wanted, n);
  for (size_t k = 0; k < m; ++k) chosen[m == 1 ? 0 : (k * (n - 1) + (m - 1) / 2) / (m - 1)] = true;
  return chosen;
}

struct SheetView {
  std::string label;
  std::vector<float> truth;  // RGB, composited over the model's background
  RenderedImage render;
};

// Depth coloured over what the views' opaque pixels span (1st to 99th percentile), one range for
// the whole sheet so that rows compare: the range `vknerf render` takes from the scene box would
// make a cup in a box around the room one colour. The box's range where no pixel is opaque.
void writeSheet(const Options& o, const std::vector<SheetView>& views, const Model& model, const Dataset& data) {
  std::vector<const RenderedImage*> renders;
  for (const SheetView& v : views) renders.push_back(&v.render);
  const nerf::DepthRange depth = nerf::depthRangeOfOpaquePixels(renders).value_or(
      nerf::depthRangeFor(nerf::meanCameraDistance(data.cameras), model.bounds()));
  char range[64], scale[64];
  std::snprintf(range, sizeof range, "depth %.2f to %.2f", depth.nearDepth, depth.farDepth);
  std::snprintf(scale, sizeof scale, "error 0 to %.2f", kSheetErrorScale);
  nerf::ContactSheet sheet(std::array<std::string, 4>{"ground truth", "render", range, scale}, o.sheetSize);
  for (const SheetView& v : views) {
    const RenderedImage& img = v.render;
    sheet.addRow(v.label, {nerf::rgbaOf({img.width, img.height, v.truth, {}, {}, {}}), nerf::rgbaOf(img),
                           nerf::depthRgba(img, depth.nearDepth, depth.farDepth),
                           nerf::errorRgba(img.rgb, v.truth, img.width, img.height, kSheetErrorScale)});
  }
  sheet.save(o.sheet);
  std::printf("wrote %s: %zu views, ground truth | render | depth | error\n", o.sheet.c_str(), sheet.rows());
}

int run(const Options& o, const Globals& g) {
  // Before the evaluation: a report that cannot be written, or would replace an input, would lose it.
  CommandFiles files("eval");
  files.input(o.model, "model").scene(o.scene).output(o.json, "--json").output(o.csv, "--csv").output(o.sheet, "--sheet");
  files.check();
  auto ctx = g.context();
  Model model = loadWithRenderSettings(ctx, o.model, o.settings, o.given, "eval");
  DatasetOptions dopt;
  dopt.split = o.split;
  dopt.downscale = o.downscale;
  dopt.progress = progressPrinter("decoding images");
  Dataset data = Dataset::load(o.scene, dopt);
  // Training views where the model learned they were: only those names the checkpoint recorded.
  if (model.config().isFast() && model.config().fastModel().refineCameras) {
    const size_t refined = nerf::useTrainedPoses(data.cameras, data.names, model.trainingCameras());
    if (refined)
      std::printf("%zu of %zu views are training photos: rendered at the poses the model refined\n", refined,
                  data.cameras.size());
  }
  size_t n = data.cameras.size();
  if (o.limit && n > o.limit) n = o.limit;
  nlohmann::json images = nlohmann::json::array();
  double sumPsnr = 0, sumSsim = 0, sumSeconds = 0, sumSamples = 0, sumPixels = 0;
  const std::vector<bool> onSheet = sheetViews(n, o.sheetViews);
  std::vector<SheetView> sheetViewsKept;  // drawn once their depths' range is known
  KernelTimes kernelSums;  // --profile
  for (size_t i = 0; i < n; ++i) {
    auto t0 = std::chrono::steady_clock::now();
    RenderedImage img = model.render(data.cameras[i], progressPrinter("rendering " + data.names[i] + ": pixels", true));
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    auto gt = vknerf::compositeOver(data.images[i], model.config().background);
    double p = nerf::psnr(img.rgb, gt), q = nerf::ssim(img.rgb, gt, img.width, img.height);
    // The samples a render shaded per pixel: what its time follows (early termination ends a ray
    // where it turns opaque, so this is under the samples a training step marches per ray).
    const double pixels = double(img.width) * img.height, perPixel = double(img.samples) / pixels;
    sumPsnr += p, sumSsim += q, sumSeconds += s, sumSamples += double(img.samples), sumPixels += pixels;
    addKernelTimes(kernelSums, img.kernelMs);
    images.push_back({{"name", data.names[i]}, {"psnr", p}, {"ssim", q}, {"seconds", s}, {"samples_per_pixel", perPixel}});
    std::printf("%-40s PSNR %6.2f dB  SSIM %.4f  %.3f s  %.1f samples a pixel\n", data.names[i].c_str(), p, q, s, perPixel);
    if (!o.sheet.empty() && onSheet[i]) {
      char label[64];
      std::snprintf(label, sizeof label, "  PSNR %.2f dB  SSIM %.3f", p, q);
      sheetViewsKept.push_back({std::filesystem::path(data.names[i]).filename().string() + label, std::move(gt), std::move(img)});
    }
  }
  nlohmann::json result = {{"model", o.model}, {"scene", o.scene}, {"split", o.split}, {"count", n},
                           {"psnr", sumPsnr / double(n)}, {"ssim", sumSsim / double(n)},
                           {"seconds_per_image", sumSeconds / double(n)}, {"samples_per_pixel", sumSamples / sumPixels},
                           {"device", ctx->describe()}, {"images", images}};
  std::printf("mean over %zu %s views: PSNR %.2f dB, SSIM %.4f, %.3f s per image, %.1f samples a pixel\n", n,
              o.split.c_str(), sumPsnr / double(n), sumSsim / double(n), sumSeconds / double(n), sumSamples / sumPixels);
  if (o.settings.profile && n) result["kernel_ms_per_image"] = printKernelProfile(kernelSums, n, sumSeconds);
  if (!o.json.empty()) writeFileAtomically(o.json, result.dump(2) + "\n");
  if (!o.csv.empty()) {
    std::ostringstream f;
    f << "name,psnr,ssim,seconds\n";
    for (auto& im : images)
      f << nerf::csvField(im["name"].get<std::string>()) << "," << im["psnr"] << "," << im["ssim"] << "," << im["seconds"] << "\n";
    writeFileAtomically(o.csv, f.str());
  }
  if (!o.sheet.empty()) writeSheet(o, sheetViewsKept, model, data);
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
  addAppearanceOption(app, o->settings.appearancePhoto);
  addMinTransmittanceOption(app, o->settings.minTransmittance);
  addProposalSamplesOption(app, o->settings.proposalSamples);
  app.add_option("--limit", o->limit, "Evaluate at most this many views (default 0: all)");
  addRenderProfileOption(app, o->settings.profile, "; in --json as kernel_ms_per_image");
  app.add_option("--sheet", o->sheet,
                 "Write a contact sheet PNG: a row per view (name, PSNR, SSIM), ground truth | render | depth "
                 "(colour-mapped as render writes it) | error (mean |render - truth| over RGB, 0 to 0.25)");
  app.add_option("--sheet-views", o->sheetViews, "Views on the sheet, spread evenly over those evaluated (0: all)");
  app.add_option("--sheet-size", o->sheetSize, "Largest side of a tile on the sheet, pixels (tiles are never enlarged)")
      ->check(CLI::Range(16u, 4096u));
  return [o, &g, &app] {
    // Without a sheet these would do nothing: refused, as every flag without effect is.
    for (const char* flag : {"--sheet-views", "--sheet-size"})
      if (app.count(flag) && o->sheet.empty())
        throw UsageError(std::string("eval: ") + flag + " has no effect without --sheet (add it, or drop " + flag + ")");
    o->given = GivenRenderFlags::of(app);
    return run(*o, g);
  };
});

}  // namespace
}  // namespace vknerf::cli

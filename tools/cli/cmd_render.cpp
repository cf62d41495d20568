// `vknerf render MODEL SCENE|--orbit N|--path PATH.json [-o DIR] [--video OUT.mp4]`: RGB, depth
// (colour-mapped PNG and raw PFM) and opacity for a split's cameras, an orbit or a camera path
// (nerfstudio's, or instant-ngp's base_cam.json sampled at --fps for --seconds at --width x
// --height), frames numbered, and/or an H.264 video of the RGB frames (through ffmpeg).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include "render_options.h"
#include "render_profile_report.h"
#include "checks.h"
#include "command_files.h"
#include "command.h"
#include "progress.h"
#include "lib/render_output.h"
#include "lib/video_encoder.h"
#include "vknerf/camera_path.h"
#include "vknerf/camera.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"
#include "vknerf/trainer.h"

namespace vknerf::cli {
namespace {

struct Options {
  std::string model, scene, outDir, split = "test", path, video;
  uint32_t orbit = 0, downscale = 1, size = 100, limit = 0;
  float elevationDegrees = 30, radius = 0;
  double fps = 0;  // 0: the path's, else 24; instant-ngp paths: 60
  // instant-ngp paths only (nerfstudio's state their own); unset: run.py's defaults.
  std::optional<double> seconds;
  std::optional<uint32_t> width, height;
  RenderSettings settings;  // --appearance, --min-transmittance, --proposal-samples, --profile
  GivenRenderFlags given;
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
  if (o.scene.empty() && o.orbit == 0 && o.path.empty())
    throw UsageError("render: give a SCENE (renders its --split cameras), --orbit N or --path PATH.json");
  if (o.orbit && !o.path.empty()) throw UsageError("render: --orbit and --path each give the cameras: choose one");
  if (o.outDir.empty() && o.video.empty()) throw UsageError("render: give -o DIR for the frames, --video OUT.mp4, or both");
  // The outputs before any rendering: a path that cannot hold them, or would replace an input, fails
  // now; the folder is created only once every input has been read.
  CommandFiles files("render");
  files.input(o.model, "model").input(o.path, "--path").scene(o.scene);
  files.outputFolder(o.outDir, "output folder").output(o.video, "--video");
  files.check();
  double fps = o.fps > 0 ? o.fps : 24;
  std::vector<Camera> pathCameras;
  if (!o.path.empty()) {
    CameraPathOptions popt;
    if (o.fps > 0) popt.fps = o.fps;
    if (o.seconds) popt.seconds = *o.seconds;
    if (o.width) popt.width = *o.width;
    if (o.height) popt.height = *o.height;
    popt.scene = o.scene;
    CameraPath path = loadCameraPath(o.path, popt);
    if (path.format == CameraPath::Format::nerfstudio && (o.seconds || o.width || o.height))
      throw UsageError("render: " + o.path +
                       " is a nerfstudio camera path, which lists its frames and their size; --seconds, --width and "
                       "--height are for instant-ngp paths (base_cam.json)");
    if (path.format == CameraPath::Format::instantNgp)
      std::printf("%s: instant-ngp camera path, %zu frames at %g frames/s; its frame: %s%s\n", o.path.c_str(),
                  path.cameras.size(), path.fps, path.frameNote.c_str(),
                  o.scene.empty() ? " (give the SCENE it was made on for that scene's scale and offset)" : "");
    pathCameras = std::move(path.cameras);
    if (o.fps <= 0) fps = path.fps;
  }
  auto ctx = g.context();
  Model model = loadWithRenderSettings(ctx, o.model, o.settings, o.given, "render");
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
    if (radius <= 0) radius = nerf::meanCameraDistance(data.cameras);
  }
  if (radius <= 0) radius = 4.0f;
  if (o.orbit) cams = orbitCameras(o.orbit, model.bounds(), radius, o.elevationDegrees, like);
  if (!pathCameras.empty()) cams = std::move(pathCameras);
  if (o.limit && cams.size() > o.limit) cams.resize(o.limit);
  files.createFolders();
  std::optional<nerf::VideoEncoder> video;
  if (!o.video.empty()) {
    for (const Camera& c : cams)
      if (c.width != cams[0].width || c.height != cams[0].height)
        throw Error("--video " + o.video + ": the views differ in size (" + std::to_string(cams[0].width) + "x" +
                    std::to_string(cams[0].height) + " and " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                    "); a video needs one size");
    video.emplace(o.video, cams[0].width, cams[0].height, fps);  // fails now when ffmpeg is missing
  }
  const nerf::DepthRange depthRange = nerf::depthRangeFor(radius, model.bounds());
  const auto start = std::chrono::steady_clock::now();
  KernelTimes kernelSums;  // --profile
  double renderSeconds = 0;
  for (size_t i = 0; i < cams.size(); ++i) {
    auto t0 = std::chrono::steady_clock::now();
    RenderedImage img = model.render(cams[i], progressPrinter("rendering view " + std::to_string(i) + ": pixels", true));
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    renderSeconds += s;
    addKernelTimes(kernelSums, img.kernelMs);
    char name[64];
    std::snprintf(name, sizeof name, "%04zu", i);
    if (!o.outDir.empty()) {
      std::string base = o.outDir + "/";
      nerf::saveRgbPng(base + "rgb_" + name + ".png", img);
      nerf::saveDepthPng(base + "depth_" + name + ".png", img, depthRange.nearDepth, depthRange.farDepth);
      nerf::saveDepthPfm(base + "depth_" + name + ".pfm", img);
      nerf::saveOpacityPng(base + "opacity_" + name + ".png", img);
    }
    if (video) video->addFrame(nerf::rgbaOf(img).rgba);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double rate = double(i + 1) / elapsed;
    std::printf("frame %s (%zu/%zu): %ux%u in %.3f s; %.2f frames/s, ETA %.0f s\n", name, i + 1, cams.size(),
                img.width, img.height, s, rate, double(cams.size() - i - 1) / rate);
    std::fflush(stdout);
  }
  if (o.settings.profile && !cams.empty()) printKernelProfile(kernelSums, cams.size(), renderSeconds);
  if (video) {
    video->finish();
    std::printf("wrote %s: %zu frames at %g frames/s\n", o.video.c_str(), cams.size(), fps);
  }
  if (!o.outDir.empty()) std::printf("wrote %zu views to %s\n", cams.size(), o.outDir.c_str());
  return 0;
}

Registration render("render", "Render RGB, depth and opacity images from a trained model", [](CLI::App& app, const Globals& g) {
  auto o = std::make_shared<Options>();
  app.add_option("model", o->model, "Model checkpoint (from vknerf train)")->required();
  app.add_option("scene", o->scene,
                 "Scene whose cameras to render (see --split); with an instant-ngp --path, the scene the path was made on");
  app.add_option("-o,--output", o->outDir, "Output folder for the frames (RGB, depth and opacity images)");
  app.add_option("--path", o->path,
                 "Render a camera path instead: nerfstudio's camera path JSON, or instant-ngp's base_cam.json "
                 "(its keyframes sampled at --fps for --seconds, at --width x --height; with SCENE, that scene's "
                 "transforms.json gives instant-ngp's scale and offset, else its defaults 0.33 and 0.5)");
  app.add_option("--video", o->video, "Also (or only) write the RGB frames as an H.264 MP4 video (needs ffmpeg)");
  app.add_option("--fps", o->fps,
                 "Video frame rate (default: the camera path's, else 24); for an instant-ngp path also the rate its "
                 "keyframes are sampled at (default 60)")
      ->check(CLI::Range(0.001, 1000.0));
  app.add_option("--seconds", o->seconds, "instant-ngp path: its duration (default 1)")->check(CLI::Range(0.001, 100000.0));
  app.add_option("--width", o->width, "instant-ngp path: frame width (default 1920)")->check(CLI::Range(1u, 16384u));
  app.add_option("--height", o->height, "instant-ngp path: frame height (default 1080)")->check(CLI::Range(1u, 16384u));
  app.add_option("--split", o->split, "Split of SCENE to render")->check(CLI::IsMember({"train", "val", "test", "all"}));
  app.add_option("--orbit", o->orbit, "Render N views on a circle around the scene instead")->check(CLI::Range(1u, 10000u));
  app.add_option("--elevation", o->elevationDegrees, "Orbit elevation in degrees")->check(FiniteNumber);
  app.add_option("--radius", o->radius, "Orbit radius (default: the scene cameras' mean distance, else 4)")->check(FiniteNumber);
  app.add_option("--size", o->size, "Orbit image size without a SCENE")->check(CLI::Range(1u, 8192u));
  app.add_option("--downscale", o->downscale, "Downscale SCENE's images by this factor")->check(CLI::Range(1u, 64u));
  addAppearanceOption(app, o->settings.appearancePhoto);
  addMinTransmittanceOption(app, o->settings.minTransmittance);
  addProposalSamplesOption(app, o->settings.proposalSamples);
  addRenderProfileOption(app, o->settings.profile);
  app.add_option("--limit", o->limit, "Render at most this many views (default 0: all)");
  return [o, &g, &app] {
    // A flag that changes nothing in this run is refused, as every flag without effect is: the
    // views come from the orbit (sized by --size alone without a SCENE), a path, or the SCENE's split.
    const auto refuse = [](const std::string& flag, const std::string& when) {
      throw UsageError("render: " + flag + " has no effect " + when);
    };
    const bool scene = !o->scene.empty(), path = !o->path.empty();
    if (app.count("--elevation") && !o->orbit) refuse("--elevation", "without --orbit");
    if (app.count("--size") && (!o->orbit || scene))
      refuse("--size", "but on an --orbit without a SCENE (a SCENE's or a path's views have their own size)");
    if (app.count("--split") && (!scene || o->orbit || path)) refuse("--split", "but on a SCENE's own views (no --orbit or --path)");
    if (app.count("--downscale") && (!scene || path)) refuse("--downscale", "without a SCENE whose views or size are rendered");
    if (app.count("--fps") && o->video.empty() && !path) refuse("--fps", "without --video or an instant-ngp --path");
    for (const char* flag : {"--seconds", "--width", "--height"})
      if (app.count(flag) && !path) refuse(flag, "without an instant-ngp --path");
    o->given = GivenRenderFlags::of(app);
    return run(*o, g);
  };
});

}  // namespace
}  // namespace vknerf::cli

// `vknerf train SCENE -o MODEL`: fit a NeRF to posed photos.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <optional>

#include <fstream>

#include <nlohmann/json.hpp>

#include "checks.h"
#include "command_files.h"
#include "command.h"
#include "config_flags.h"
#include "progress.h"
#include "step_profile_report.h"
#include "vknerf/checkpoint_scene.h"
#include "vknerf/dataset.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"
#include "vknerf/trainer.h"

namespace vknerf::cli {
namespace {

// SIGINT or SIGTERM ends training at the next step boundary, saves the checkpoint and exits
// 128 + the signal's number. The handler only records the signal (async-signal-safe); a second
// signal while that save runs means "now": it exits at once, and the atomic writer guarantees the
// checkpoint on disk is the previous complete one (its temporary file is removed).
// Once the last checkpoint is saved nothing is left to save: a signal then ends the run at once,
// so that writing --summary into a pipe nobody reads (its open blocks) cannot outlive it.
volatile std::sig_atomic_t stopSignal = 0, finalSaveDone = 0;
extern "C" void onStopSignal(int sig) {
  if (stopSignal || finalSaveDone) {
    removeTemporaryFiles();
    ::_exit(128 + sig);
  }
  stopSignal = sig;
}

struct Options {
  // fast by default: the NeRF paper's model reaches a fast model's quality only in ten times the
  // time (docs/performance.md), and is there to compare against, asked for by name.
  std::string scene, output, config = "fast", summary;
  uint32_t steps = 0, downscale = 1, logEvery = 50, saveEvery = 1000;
  double seconds = 0;
  bool resume = false, profile = false;
  uint32_t profileSteps = 1;
  bool configGiven = false;  // its default is also a valid value
  bool profileStepsGiven = false;
  std::shared_ptr<const ConfigFlags> configFlags;  // --rays ... --seed: the fields they set
};

std::string clock(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%d:%02d", int(s) / 60, int(s) % 60);
  return buf;
}

int train(const Options& o, const Globals& g);

// A resumed run keeps the checkpoint's configuration: a flag asking for something else would be
// silently ignored, so name it and the checkpoint's value instead.
void checkAgainstCheckpoint(const Options& o, const TrainConfig& saved) {
  const auto conflict = [&](const std::string& flag, const std::string& given, const std::string& stored) {
    throw UsageError("train: " + flag + " " + given + " conflicts with " + o.output + "'s " + stored +
                     " (--resume keeps the checkpoint's configuration; drop the flag or write a new model)");
  };
  if (o.configGiven && o.config != modelName(saved.model))
    conflict("--config", o.config, std::string("model ") + modelName(saved.model));
  if (const std::string wrong = o.configFlags->forTheOtherModel(saved); !wrong.empty())
    conflict(wrong, "", std::string(modelName(saved.model)) + " model");
  if (const auto c = o.configFlags->conflictWith(saved)) conflict(c->flag, c->asked, c->stored);
}

// Only a checkpoint (or an empty file) may be replaced by one: anything else at the output path is
// someone's data, and overwriting it is never what was meant.
void checkReplaceable(const std::string& output) {
  std::error_code ec;
  if (!std::filesystem::exists(output, ec) || std::filesystem::is_empty(output, ec) || looksLikeCheckpoint(output)) return;
  throw Error("model " + output + ": exists and is not a vknerf checkpoint; refusing to overwrite it");
}

int run(const Options& o, const Globals& g) {
  Options opts = o;
  if (opts.output.empty()) {
    // `vknerf train assets/tabletop` writes tabletop.vknerf in the working directory.
    auto p = std::filesystem::path(opts.scene);
    std::string stem = (p.has_filename() ? p : p.parent_path()).stem().string();
    if (stem.rfind("transforms", 0) == 0) stem = std::filesystem::absolute(p).parent_path().filename().string();
    opts.output = (stem.empty() ? "model" : stem) + ".vknerf";
  }
  // Before any work, which a bad path would lose. With --resume the model is read too: by design.
  if (opts.profileStepsGiven && !opts.profile)
    throw UsageError("train: --profile-steps has no effect without --profile (add it, or drop --profile-steps)");
  CommandFiles files("train");
  files.scene(opts.scene).output(opts.output, "model").output(opts.summary, "--summary");
  files.check();
  checkReplaceable(opts.output);
  if (opts.steps == 0 && opts.seconds <= 0) {
    opts.seconds = 300;  // converges to a usable model on a CPU device; say so, since it was not asked for
    std::printf("no --steps or --time given: training for %.0f s\n", opts.seconds);
  }
  return train(opts, g);
}

// "800x800", or "800x800 to 1920x1080" when the frames differ in size.
std::string imageSizes(const Dataset& data) {
  auto pixels = [](const ImageRGBA8& im) { return uint64_t(im.width) * im.height; };
  const ImageRGBA8 *lo = &data.images[0], *hi = lo;
  for (const auto& im : data.images) {
    if (pixels(im) < pixels(*lo)) lo = &im;
    if (pixels(im) > pixels(*hi)) hi = &im;
  }
  auto text = [](const ImageRGBA8& im) { return std::to_string(im.width) + "x" + std::to_string(im.height); };
  return pixels(*lo) == pixels(*hi) ? text(*lo) : text(*lo) + " to " + text(*hi);
}

// --summary: what `bench scenes` (and any script) reads of a run, rather than parsing the log.
void writeSummary(const std::string& path, const Trainer& trainer, double seconds, double lastPsnr, bool interrupted) {
  const ModelStatistics s = trainer.statistics();
  const double images = trainer.trainingPixelsDeviceMiB();
  nlohmann::json j = {{"steps", trainer.steps()},
                      {"seconds", seconds},
                      {"interrupted", interrupted},
                      {"samples_per_ray", s.meanSamplesPerRay.value_or(s.samplesPerRay)},
                      {"device_mib", s.deviceMiB + images},
                      {"model_device_mib", s.deviceMiB},
                      {"training_images_device_mib", images},
                      {"host_peak_mib", hostPeakMiB()},
                      {"train_psnr", lastPsnr >= 0 ? nlohmann::json(lastPsnr) : nlohmann::json()},
                      {"config", trainer.model().config().describe()}};
  writeFileAtomically(path, j.dump(2) + "\n");
}

int train(const Options& o, const Globals& g) {
  auto ctx = g.context();
  DatasetOptions dopt;
  dopt.downscale = o.downscale;
  dopt.progress = progressPrinter("decoding images");
  Dataset data = Dataset::load(o.scene, dopt);
  std::printf("scene: %zu training images of %s from %s; box [%.2f %.2f %.2f]..[%.2f %.2f %.2f] (%s)\n",
              data.images.size(), imageSizes(data).c_str(), o.scene.c_str(), data.bounds.min[0],
              data.bounds.min[1], data.bounds.min[2], data.bounds.max[0], data.bounds.max[1], data.bounds.max[2],
              data.boundsSource.c_str());
  const bool resuming = o.resume && std::filesystem::exists(o.output);
  TrainConfig cfg = resuming ? Trainer::configOf(o.output) : TrainConfig::named(o.config, *ctx);
  if (resuming) {
    checkAgainstCheckpoint(o, cfg);
  } else {
    if (const std::string wrong = o.configFlags->forTheOtherModel(cfg); !wrong.empty())
      throw UsageError("train: " + wrong + " applies to the " + (cfg.isFast() ? "vanilla" : "fast") +
                       " model, not --config " + o.config +
                       (o.configGiven ? "" : " (the default; add --config vanilla for the NeRF paper's model)"));
    o.configFlags->applyTo(cfg);
    try {
      cfg.validate();
    } catch (const Error& e) {
      throw UsageError(std::string("train: the configuration from these flags is invalid: ") + e.what());
    }
  }
  // A flag that tunes a switch left off would do nothing: refused, as a flag of the other model is.
  if (cfg.isFast() && !cfg.fastModel().refineCameras)
    for (const char* flag : {"--camera-lr", "--camera-penalty"})
      if (o.configFlags->given(flag))
        throw UsageError(std::string("train: ") + flag + " has no effect without --refine-cameras (add it, or drop " + flag + ")");
  // The proposal's flags tune it where it is chosen (asked for, or left to the photos).
  if (cfg.isFast() && cfg.fastModel().sampler == Sampler::March)
    for (const char* flag : {"--proposal-levels", "--proposal-stride", "--proposal-anneal-steps"})
      if (o.configFlags->given(flag))
        throw UsageError(std::string("train: ") + flag + " has no effect with --proposal-samples 0 (the march; drop " + flag + ")");
  std::printf("config: %s\n", cfg.describe().c_str());
  std::optional<Trainer> built;
  try {
    built.emplace(ctx, std::move(data), cfg);  // the host copy goes as the device's fills
  } catch (const OutOfMemoryError& e) {
    throw Error(std::string(e.what()) + " while building the model for " + std::to_string(cfg.raysPerBatch) +
                " rays per batch; lower --rays" + (cfg.isFast() ? " or --samples-per-step" : "") + " or raise --downscale");
  }
  Trainer& trainer = *built;
  if (!trainer.capacityNote().empty()) std::printf("%s\n", trainer.capacityNote().c_str());
  if (cfg.isFast()) {
    const ModelStatistics start = trainer.statistics();
    std::printf("model: %zu occupancy cascade(s) over the box (aabb_scale %g), device buffers %.1f MiB\n",
                std::max<size_t>(1, start.occupiedFractionPerCascade.size()), double(data.aabbScale), start.deviceMiB);
  }
  if (resuming) {
    trainer.resume(o.output);
    std::printf("resumed %s at step %u\n", o.output.c_str(), trainer.steps());
  }
  if (uint64_t(trainer.steps()) + o.steps > UINT32_MAX)
    throw UsageError("train: --steps " + std::to_string(o.steps) + " from step " + std::to_string(trainer.steps()) +
                     " passes the step counter's limit of " + std::to_string(UINT32_MAX));
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
  const bool tty = ::isatty(fileno(stdout));
  const uint32_t first = trainer.steps();
  const uint32_t last = o.steps ? first + o.steps : UINT32_MAX;
  // Training time: the wall time since the loop began, less the time spent compiling kernels (the
  // first step's, on lavapipe), which --time, the rates and the ETA leave out.
  auto t0 = std::chrono::steady_clock::now();
  const double compiledBefore = ctx->compileStats().seconds;
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() -
           (ctx->compileStats().seconds - compiledBefore);
  };
  // How much of the run is done: by steps, by time, or the further of the two when both are given.
  auto runFraction = [&] {
    const double s = elapsed(), done = double(trainer.steps() - first);
    if (o.steps && o.seconds > 0) return std::max(done / o.steps, s / o.seconds);
    return o.steps ? done / o.steps : s / o.seconds;
  };
  // The rates decay over this run's budget. A resumed run keeps the step schedule instead: its
  // budget is what is left, and a decay restarted over it would throw the rates back up to lr.
  if (resuming)
    std::printf("learning rate: %.3g, as the schedule stands at step %u (decay_steps %u, then held)\n",
                trainer.learningRate(), trainer.steps(), cfg.decaySteps);
  else
    std::printf("learning rate: %g -> %g over this run's %s\n", double(cfg.learningRate), double(cfg.learningRateFinal),
                o.steps && o.seconds > 0 ? "steps or time, whichever ends it" : o.steps ? "steps" : "time");
  std::deque<StepProfile> profiles;  // --profile: the last --profile-steps steps'
  double lastPsnr = -1;  // none measured yet: the loss is read every --log-every steps
  // A step's statistics arrive when the next step has been submitted (Trainer::submitStep): the
  // line for step N is printed then, or after the loop for the last one.
  auto report = [&](const StepStats& st) {
    if (!st.hasLoss) return;
    lastPsnr = st.psnr;
    double s = elapsed(), done = double(st.step - first);
    double rate = done / s, frac = runFraction();
    double eta = frac > 0 ? s / frac - s : 0;
    // The loss is the photometric term (its PSNR beside it); the other terms follow by name.
    std::string terms;
    for (const auto& [name, value] : st.lossTerms) {
      char term[96];
      std::snprintf(term, sizeof term, "  %s %.3g", name.c_str(), value);
      terms += term;
    }
    char line[512];
    std::snprintf(line, sizeof line, "step %6u  loss %.5f  train PSNR %5.2f dB%s  %7.0f rays/s  %s elapsed  ETA %s",
                  st.step, st.loss, st.psnr, terms.c_str(), rate * st.rays, clock(s).c_str(), clock(eta).c_str());
    if (tty) {
      int bar = int(std::min(1.0, frac) * 20);
      std::printf("\r[%.*s%*s] %s", bar, "####################", 20 - bar, "", line);
      std::fflush(stdout);
    } else {
      std::printf("%s\n", line);
    }
  };
  while (trainer.steps() < last && !(o.seconds > 0 && elapsed() >= o.seconds) && !stopSignal) {
    const bool readLoss = (trainer.steps() + 1) % o.logEvery == 0 || trainer.steps() + 1 == last;
    if (!resuming) trainer.setRunProgress(runFraction());
    if (o.profile) {
      // A profile times one step at a time: each step waited for, its kernels alone on the device.
      report(trainer.step(readLoss));
      profiles.push_back(trainer.lastStepProfile());
      if (profiles.size() > o.profileSteps) profiles.pop_front();
    } else if (auto done = trainer.submitStep(readLoss)) {
      report(*done);
    }
    if (o.saveEvery && trainer.steps() % o.saveEvery == 0) trainer.save(o.output);
  }
  // The last step; also the one a save waited for when it was the last.
  if (auto done = trainer.finishSteps()) report(*done);
  if (tty) std::printf("\n");
  for (auto& [name, value] : statisticsRows(trainer.statistics())) std::printf("  %-48s %g\n", name.c_str(), value);
  std::printf("memory: host peak %.1f MiB; device %.1f MiB (model %.1f MiB + training images %.1f MiB in %u buffers)\n",
              hostPeakMiB(), trainer.statistics().deviceMiB + trainer.trainingPixelsDeviceMiB(),
              trainer.statistics().deviceMiB, trainer.trainingPixelsDeviceMiB(), trainer.trainingPixelBindings());
  if (o.profile && !profiles.empty()) printStepProfile({profiles.begin(), profiles.end()});
  trainer.save(o.output);
  finalSaveDone = 1;
  const CompileStats compiled = ctx->compileStats();
  std::printf("kernels: %.1f s compiling (%u pipelines, %u compiled ahead), not counted in the training time\n",
              compiled.seconds, compiled.pipelines, compiled.compiledAhead);
  char psnr[64] = "no train PSNR measured: fewer steps than --log-every";
  if (lastPsnr >= 0) std::snprintf(psnr, sizeof psnr, "last train PSNR %.2f dB", lastPsnr);
  std::printf("%s after %u steps (%.1f s, %s); model saved to %s\n", stopSignal ? "interrupted" : "done",
              trainer.steps(), elapsed(), psnr, o.output.c_str());
  if (!o.summary.empty()) writeSummary(o.summary, trainer, elapsed(), lastPsnr, bool(stopSignal));
  return stopSignal ? 128 + stopSignal : 0;
}

Registration trainCommand("train", "Train a NeRF on a scene (nerf_synthetic/instant-ngp transforms JSON, COLMAP model (text or binary) or LLFF poses_bounds.npy)",
                   [](CLI::App& app, const Globals& g) {
                     auto o = std::make_shared<Options>();
                     app.add_option("scene", o->scene, "Scene folder, transforms JSON file, COLMAP model (text or binary), or LLFF poses_bounds.npy")->required();
                     app.add_option("-o,--output", o->output, "Model checkpoint to write (default: <scene name>.vknerf)");
                     app.add_option("--config", o->config, "Model configuration: fast (default; hash grid + occupancy grid) or vanilla (NeRF paper)")->check(CLI::IsMember({"fast", "vanilla"}));
                     app.add_option("--steps", o->steps, "Number of training steps");
                     app.add_option("--time", o->seconds, "Wall-clock budget in seconds (default without --steps: 300)")->check(PositiveFinite);
                     app.add_option("--downscale", o->downscale, "Downscale images by this factor")->check(CLI::Range(1u, 64u));
                     o->configFlags = std::make_shared<ConfigFlags>(app);
                     app.add_option("--log-every", o->logEvery, "Report the loss every K steps")->check(CLI::Range(1u, 1000000u));
                     app.add_option("--save-every", o->saveEvery, "Write the checkpoint every K steps (0: only at the end)");
                     app.add_flag("--profile", o->profile, "Print where the last step's time went: each submission's kernels, the host time between them (the steps then run one at a time, each waited for)");
                     app.add_option("--profile-steps", o->profileSteps, "With --profile: over the last K steps, each figure its median over them (steadier on a busy machine)")->check(CLI::Range(1u, 100000u));
                     app.add_option("--summary", o->summary, "Also write the run's numbers as JSON: steps, seconds, samples per ray (mean over all steps), device and host MiB, last train PSNR");
                     app.add_flag("--resume", o->resume, "Continue from MODEL if it exists (its config is kept; flags must agree with it)");
                     return [o, &g, &app] {
                       o->configGiven = app.count("--config") > 0;
                       o->profileStepsGiven = app.count("--profile-steps") > 0;
                       return run(*o, g);
                     };
                   });

}  // namespace
}  // namespace vknerf::cli

// `vknerf bench scenes SCENE... (--time S | --steps N) -o DIR`: quality over several scenes, one
// table. Each scene is trained with the same flags and evaluated on its held-out views by child
// processes of one or more builds (--vknerf, default this one), interleaved per scene; DIR gets
// scenes.md, scenes.csv and a contact sheet per scene and build (lib/bench/).
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>

#include "checks.h"
#include "command.h"
#include "command_files.h"
#include "lib/bench/run_plan.h"
#include "lib/bench/scene_run.h"
#include "lib/bench/scene_table.h"
#include "lib/process/subprocess.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"

namespace vknerf::cli {
namespace {

namespace fs = std::filesystem;

struct Options {
  std::vector<std::string> scenes, trainArgs, binaries;
  std::string out, config = "fast", split = "test";
  double seconds = 0;
  uint32_t steps = 0, downscale = 1;
  std::optional<uint32_t> sheetViews, sheetSize;  // eval's defaults unless given
};

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

int run(const Options& o, const Globals& g) {
  if (o.steps == 0 && o.seconds <= 0) throw UsageError("bench scenes: give a budget, --time S or --steps N");
  // Everything that can be checked before hours of training: the scenes, the builds, the folder.
  std::vector<std::string> names;
  std::set<std::string> seenScenes;
  for (const std::string& scene : o.scenes) {
    std::error_code ec;
    if (!fs::exists(scene, ec)) throw Error("scene " + scene + ": does not exist");
    names.push_back(bench::sceneName(scene));
    if (!seenScenes.insert(names.back()).second)
      throw UsageError("bench scenes: two scenes are named " + names.back() + " (the table names a scene by its folder)");
  }
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  const std::vector<std::string> arguments = o.binaries.empty() ? std::vector<std::string>{self} : o.binaries;
  for (const std::string& a : arguments) {
    // NAME=BINARY with either side missing would otherwise be read as a path, or as a build of no file.
    const size_t eq = a.find('='), slash = a.find('/');
    if (eq == std::string::npos || (slash != std::string::npos && slash < eq)) continue;
    if (eq == 0) throw UsageError("bench scenes: --vknerf " + a + ": no name before '=' (give NAME=BINARY, or the BINARY alone)");
    if (eq + 1 == a.size()) throw UsageError("bench scenes: --vknerf " + a + ": no binary after '=' (give NAME=BINARY)");
  }
  std::vector<std::string> buildNames;
  try {
    buildNames = bench::buildNames(arguments);
  } catch (const Error& e) {
    throw UsageError(std::string("bench scenes: ") + e.what());  // two builds of one name: the flags' fault
  }
  std::set<std::string> seenBinaries;
  for (const std::string& a : arguments) {
    const std::string path = bench::buildPath(a);
    if (::access(path.c_str(), X_OK) != 0) throw Error("--vknerf " + path + ": not an executable file");
    std::error_code ec;
    if (!seenBinaries.insert(fs::weakly_canonical(path, ec).string()).second)
      throw UsageError("bench scenes: --vknerf " + path + " is given twice");
  }
  // -o may neither hold nor lie in a scene, nor be a build; it is made only once all of that holds.
  CommandFiles files("bench scenes");
  for (const std::string& scene : o.scenes) files.scene(scene);
  for (const std::string& a : arguments) files.input(bench::buildPath(a), "--vknerf");
  files.outputFolder(o.out, "-o").output((fs::path(o.out) / "scenes.md").string(), "-o");
  files.check();
  // Stopped, this command passes the signal on to the run in progress and waits for it (a `train`
  // saves its model first), starts no other and reports; it never leaves a child running.
  process::forwardStopSignals();
  // A build that does not answer --help (not a vknerf) fails here, before -o is made.
  std::vector<bench::Build> builds;
  for (size_t i = 0; i < arguments.size(); ++i) builds.push_back(bench::probeBuild(buildNames[i], bench::buildPath(arguments[i]), self));
  const bench::Build selfBuild = bench::probeBuild("this", self, self);
  if (const int sig = process::stopSignalReceived()) return 128 + sig;
  // A flag a build's train does not know would fail each of its runs, the first after minutes of
  // others: found now. Its value is the build's to check, when the run starts.
  for (const bench::Build& b : builds)
    for (const std::string& a : o.trainArgs)
      if (a.rfind("--", 0) == 0 && !bench::listsFlag(b.trainHelp, a.substr(0, a.find('='))))
        throw UsageError("bench scenes: --train-arg " + a + ": the train of build " + b.name + " (" + b.binary +
                         ") has no flag " + a.substr(0, a.find('=')));
  files.createFolders();

  bench::SceneRunSettings s;
  if (!g.device.empty()) s.globalArgs = {"--device", g.device};
  if (g.validation) s.globalArgs.push_back("--validation");
  if (o.steps) s.trainArgs.insert(s.trainArgs.end(), {"--steps", std::to_string(o.steps)});
  if (o.seconds > 0) s.trainArgs.insert(s.trainArgs.end(), {"--time", number(o.seconds)});
  s.trainArgs.insert(s.trainArgs.end(), {"--config", o.config, "--downscale", std::to_string(o.downscale)});
  s.trainArgs.insert(s.trainArgs.end(), o.trainArgs.begin(), o.trainArgs.end());
  s.evalArgs = {"--split", o.split, "--downscale", std::to_string(o.downscale)};
  if (o.sheetViews) s.sheetArgs.insert(s.sheetArgs.end(), {"--sheet-views", std::to_string(*o.sheetViews)});
  if (o.sheetSize) s.sheetArgs.insert(s.sheetArgs.end(), {"--sheet-size", std::to_string(*o.sheetSize)});
  s.dir = o.out;
  s.labelByBuild = builds.size() > 1;
  s.say = [](const std::string& line) { std::printf("%s\n", line.c_str()); };

  std::vector<bench::SceneRow> rows;
  for (size_t i = 0; i < o.scenes.size() && !process::stopSignalReceived(); ++i)
    for (size_t b : bench::buildOrder(i, builds.size())) {
      if (process::stopSignalReceived()) break;
      std::printf("[%zu/%zu] %s, build %s\n", i + 1, o.scenes.size(), names[i].c_str(), builds[b].name.c_str());
      rows.push_back(bench::runScene(o.scenes[i], names[i], builds[b], selfBuild, s));
      const bench::SceneRow& r = rows.back();
      if (r.failed)
        std::printf("%s on %s: %s\n", r.build.c_str(), r.scene.c_str(), r.status.c_str());
      else
        std::printf("%s on %s: PSNR %.2f dB, SSIM %.3f, %u steps\n", r.build.c_str(), r.scene.c_str(), *r.psnr, *r.ssim,
                    r.steps.value_or(0));
    }

  // No child is left to pass a signal to: from here one ends the command, as in every other, so
  // that writing the table into a pipe nobody reads cannot outlive it.
  removeTemporaryFilesOnSignals();
  // The table lists the scenes, and the builds on each, in the order given (not the order run).
  const auto key = [&](const bench::SceneRow& r) {
    return std::pair(std::find(names.begin(), names.end(), r.scene) - names.begin(),
                     std::find(buildNames.begin(), buildNames.end(), r.build) - buildNames.begin());
  };
  std::stable_sort(rows.begin(), rows.end(), [&](const bench::SceneRow& a, const bench::SceneRow& b) { return key(a) < key(b); });
  std::string preamble = "Device: " + g.context()->describe() + "  \nBudget: " +
                         (o.steps ? std::to_string(o.steps) + " steps" : "") + (o.steps && o.seconds > 0 ? ", at most " : "") +
                         (o.seconds > 0 ? number(o.seconds) + " s of training" : "") + "; train flags: `";
  for (size_t i = 0; i < s.trainArgs.size(); ++i) preamble += (i ? " " : "") + s.trainArgs[i];
  preamble += "`; held-out split: " + o.split + "  \nBuilds:";
  for (const bench::Build& b : builds) preamble += " " + b.name + " = `" + b.binary + "`" + (b.self ? " (this one)" : "") + ";";
  preamble.back() = '\n';
  preamble += "\nPeak host MiB: the larger of the train and eval processes' ru_maxrss. Device MiB: the device buffers "
              "held when training ends (model and training images), as train reports them. Sheets: ground truth | "
              "render | depth | error (mean |render - truth| over RGB, 0 to 0.25), one row per view.\n";
  const fs::path dir = o.out;
  writeFileAtomically((dir / "scenes.csv").string(), bench::sceneTableCsv(rows));
  const std::string md = bench::sceneTableMarkdown(rows, preamble);
  writeFileAtomically((dir / "scenes.md").string(), md);
  const size_t failed = std::count_if(rows.begin(), rows.end(), [](const bench::SceneRow& r) { return r.failed; });
  std::printf("\n%s\nwrote %s/{scenes.md,scenes.csv}%s\n", md.c_str(), o.out.c_str(),
              failed ? (", " + std::to_string(failed) + " of " + std::to_string(rows.size()) + " runs failed").c_str() : "");
  if (const int sig = process::stopSignalReceived()) {
    std::fprintf(stderr, "vknerf: bench scenes: stopped by %s after %zu of %zu runs; the run in progress was passed the "
                 "signal and ended before this one (its row says how)\n", sig == SIGINT ? "SIGINT" : "SIGTERM", rows.size(),
                 o.scenes.size() * builds.size());
    return 128 + sig;
  }
  return failed ? 1 : 0;
}

Registration benchScenes(
    "bench scenes",
    "Held-out quality over several scenes: train and evaluate each with the same flags (and builds, --vknerf), one table and a contact sheet per scene",
    [](CLI::App& app, const Globals& g) {
      auto o = std::make_shared<Options>();
      app.add_option("scenes", o->scenes, "Scene folders (or transforms JSON files, COLMAP models, LLFF poses_bounds.npy files); the table names each by its folder")->required();
      app.add_option("-o,--out", o->out, "Output folder: scenes.md, scenes.csv, <scene>[-<build>].png, runs/ (models, logs)")->required();
      app.add_option("--time", o->seconds, "Training budget per scene, seconds")->check(PositiveFinite);
      app.add_option("--steps", o->steps, "Training budget per scene, steps (with --time: whichever ends first)")->check(CLI::Range(1u, 100000000u));
      app.add_option("--config", o->config, "Model configuration to train (default: fast)")->check(CLI::IsMember({"vanilla", "fast"}));
      app.add_option("--downscale", o->downscale, "Downscale images by this factor, in training and evaluation")->check(CLI::Range(1u, 64u));
      app.add_option("--split", o->split, "Split to evaluate")->check(CLI::IsMember({"train", "val", "test", "all"}));
      app.add_option("--sheet-views", o->sheetViews, "Views on each contact sheet (eval's default: 8; 0: all)");
      app.add_option("--sheet-size", o->sheetSize, "Largest side of a sheet's tiles, pixels (eval's default: 100)")->check(CLI::Range(16u, 4096u));
      // One value per occurrence, so that a scene after --vknerf BINARY is not taken for a second binary.
      app.add_option("--train-arg", o->trainArgs, "One more argument for every train, as --train-arg=--distortion-loss=0.001 (repeatable)")
          ->allow_extra_args(false);
      app.add_option("--vknerf", o->binaries,
                     "A build's vknerf binary, or NAME=BINARY (repeatable: builds are compared in one sitting, "
                     "their order alternating per scene; default: this one)")
          ->allow_extra_args(false);
      return [o, &g] { return run(*o, g); };
    });

}  // namespace
}  // namespace vknerf::cli

#include "lib/bench/scene_run.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <sstream>

#include "lib/bench/run_reports.h"
#include "lib/process/subprocess.h"
#include "vknerf/error.h"

namespace vknerf::bench {
namespace {

namespace fs = std::filesystem;
using Args = std::vector<std::string>;

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": not written");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

Args concat(std::initializer_list<Args> parts) {
  Args out;
  for (const Args& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// The output of `binary args...` (stdout and stderr), for --help.
std::string outputOf(const Args& argv) {
  std::string text;
  process::Subprocess p{argv, {}, "", "/dev/null", [&](const std::string& line) { text += line + "\n"; }};
  if (process::runLogged(p) != 0) throw Error(argv[0] + " " + argv[1] + " --help: failed");
  return text;
}

struct Child {
  int code = 0;
  double peakHostMiB = 0;
};

// Runs one child with its output in `log` (replaced), passing on its complaints and, unless it only
// draws a sheet (whose numbers are not the row's), its progress.
Child run(const Args& argv, const fs::path& log, const std::string& label, const SceneRunSettings& s,
          bool showProgress = true) {
  fs::remove(log);
  const auto onLine = [&](const std::string& line) {
    const bool progress = showProgress && (line.rfind("step ", 0) == 0 || line.rfind("mean over ", 0) == 0);
    const bool complaint = line.rfind("vknerf: ", 0) == 0 && line.rfind("vknerf: device ", 0) != 0;
    if (s.say && (progress || complaint)) s.say("  " + label + ": " + line);
  };
  process::ChildUsage usage;
  Child c;
  c.code = process::runLogged({argv, {}, "", log.string(), onLine}, &usage);
  c.peakHostMiB = usage.peakHostMiB;
  return c;
}

std::string failure(const char* what, const Child& c, const fs::path& log) {
  return std::string(what) + " failed (exit " + std::to_string(c.code) + "): " + process::lastLogLine(log.string());
}

}  // namespace

bool listsFlag(const std::string& help, const std::string& flag) {
  // As CLI11 lists it: "  --steps UINT", "  -o,--output TEXT", "  --profile" at the end of a line.
  for (size_t at = help.find(flag); at != std::string::npos; at = help.find(flag, at + 1)) {
    const char before = at ? help[at - 1] : ' ', after = at + flag.size() < help.size() ? help[at + flag.size()] : '\n';
    if ((before == ' ' || before == ',') && (after == ' ' || after == '\n' || after == ',')) return true;
  }
  return false;
}

Build probeBuild(const std::string& name, const std::string& binary, const std::string& selfBinary) {
  Build b{name, binary};
  std::error_code ec;
  b.self = fs::equivalent(binary, selfBinary, ec);
  b.trainHelp = outputOf({binary, "train", "--help"});
  b.hasSummary = listsFlag(b.trainHelp, "--summary");
  b.hasSheet = outputOf({binary, "eval", "--help"}).find("--sheet") != std::string::npos;
  return b;
}

SceneRow runScene(const std::string& scenePath, const std::string& scene, const Build& build, const Build& self,
                  const SceneRunSettings& s) {
  SceneRow row{scene, build.name};
  const std::string label = s.labelByBuild ? scene + "-" + build.name : scene;
  const fs::path runs = s.dir / "runs", model = runs / (label + ".vknerf"), summary = runs / (label + ".train.json"),
                 evalJson = runs / (label + ".eval.json");
  const std::string sheetName = label + ".png", sheet = (s.dir / sheetName).string();
  try {
    fs::create_directories(runs);
    fs::remove(summary), fs::remove(evalJson);  // a report left by an earlier run must not be read as this one's
    if (s.say) s.say(label + ": training with " + build.binary);
    const Args summaryArgs = build.hasSummary ? Args{"--summary", summary.string()} : Args{};
    const Child trained = run(concat({{build.binary}, s.globalArgs, {"train", scenePath, "-o", model.string()}, s.trainArgs, summaryArgs}),
                              runs / (label + ".train.log"), label, s);
    row.hostMiB = trained.peakHostMiB;
    if (trained.code != 0) {
      row.failed = true, row.status = failure("train", trained, runs / (label + ".train.log"));
      return row;
    }
    const TrainReport t = build.hasSummary ? readTrainSummary(readText(summary), summary.string())
                                           : parseTrainLog(readText(runs / (label + ".train.log")));
    row.steps = t.steps, row.samplesPerRay = t.samplesPerRay, row.deviceMiB = t.deviceMiB;

    if (s.say) s.say(label + ": evaluating");
    const Args sheetArgs = build.self ? concat({{"--sheet", sheet}, s.sheetArgs}) : Args{};
    const Child evaluated = run(concat({{build.binary}, s.globalArgs, {"eval", model.string(), scenePath, "--json", evalJson.string()}, s.evalArgs, sheetArgs}),
                                runs / (label + ".eval.log"), label, s);
    row.hostMiB = std::max(*row.hostMiB, evaluated.peakHostMiB);
    if (evaluated.code != 0) {
      row.failed = true, row.status = failure("eval", evaluated, runs / (label + ".eval.log"));
      return row;
    }
    const EvalReport e = readEvalJson(readText(evalJson), evalJson.string());
    row.psnr = e.psnr, row.ssim = e.ssim, row.secondsPerView = e.secondsPerView, row.renderSamplesPerPixel = e.samplesPerPixel;
    if (build.self) {
      row.sheet = sheetName;
      return row;
    }
    // Another build's model: the newest code draws its sheet, so that every build's sheet looks
    // the same; the build's own eval when the newest cannot load the model and the build can draw.
    const fs::path sheetLog = runs / (label + ".sheet.log");
    const Args draw = concat({{"eval", model.string(), scenePath, "--sheet", sheet}, s.evalArgs, s.sheetArgs});
    if (s.say) s.say(label + ": drawing its sheet with " + self.binary);
    Child drawn = run(concat({{self.binary}, s.globalArgs, draw}), sheetLog, label, s, false);
    if (drawn.code != 0 && build.hasSheet) drawn = run(concat({{build.binary}, s.globalArgs, draw}), sheetLog, label, s, false);
    if (drawn.code == 0)
      row.sheet = sheetName;
    else
      row.status = "ok; no sheet: " + process::lastLogLine(sheetLog.string());
  } catch (const std::exception& e) {
    row.failed = true, row.status = e.what();
  }
  return row;
}

}  // namespace vknerf::bench

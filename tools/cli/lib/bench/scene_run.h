#pragma once
// One scene with one build in `bench scenes`: `vknerf train`, then `vknerf eval` of its model, each
// a child process of the build's binary, so that its peak host memory is its own (wait4's
// ru_maxrss) and its failure is a row of the table rather than the end of the benchmark. Models,
// logs and the runs' reports go to DIR/runs/, the contact sheet to DIR/<label>.png.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "lib/bench/scene_table.h"

namespace vknerf::bench {

struct Build {
  std::string name, binary;
  bool self = false;        // the running vknerf, which writes the sheets of every build's models
  bool hasSummary = false;  // train --summary (else its printed output is parsed)
  bool hasSheet = false;    // eval --sheet
  std::string trainHelp;    // its train --help, which lists the flags a --train-arg may name
};

// Whether `help` (a command's --help) lists the long flag `flag` ("--distortion-loss").
bool listsFlag(const std::string& help, const std::string& flag);

// `binary`'s train and eval --help say which of the newer flags it has. Throws vknerf::Error when
// it does not run.
Build probeBuild(const std::string& name, const std::string& binary, const std::string& selfBinary);

struct SceneRunSettings {
  std::vector<std::string> globalArgs;  // before the command: --device, --validation
  std::vector<std::string> trainArgs;   // after `train SCENE -o MODEL`: budget, --config, --downscale, ...
  std::vector<std::string> evalArgs;    // after `eval MODEL SCENE`: --split, --downscale
  std::vector<std::string> sheetArgs;   // with every --sheet: --sheet-views, --sheet-size
  std::filesystem::path dir;
  bool labelByBuild = false;            // several builds: files are <scene>-<build>.*
  std::function<void(const std::string& line)> say;
};

// Never throws for what a run does: a failure is the row's status.
SceneRow runScene(const std::string& scenePath, const std::string& scene, const Build& build, const Build& self,
                  const SceneRunSettings& settings);

}  // namespace vknerf::bench

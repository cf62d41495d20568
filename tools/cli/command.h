#pragma once
// Each vknerf subcommand lives in its own tools/cli/cmd_*.cpp and registers itself at static-init
// time, so commands are added without touching main.cpp. A path like "bench mlp" nests commands.
#include <CLI/CLI.hpp>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "vknerf/context.h"
#include "vknerf/trainer.h"

namespace vknerf::cli {

// Options every command sees (parsed from the top level: `vknerf --device 1 train ...`).
struct Globals {
  std::string device;
  bool validation = false;
  std::shared_ptr<Context> context() const;  // created on first use, printed once
};

// `setup` adds the command's options to `app` and returns the action run after parsing; the action
// returns the exit code (0 ok, 1 runtime error); throwing vknerf::Error also gives exit code 1.
using Setup = std::function<std::function<int()>(CLI::App& app, const Globals& globals)>;

struct Registration {
  Registration(std::string path, std::string help, Setup setup);
};

struct Command {
  std::string path, help;
  Setup setup;
};
std::vector<Command>& commands();

// A model's statistics as named rows for printing and bench.md (the fast model's rows only for it).
std::vector<std::pair<std::string, double>> statisticsRows(const ModelStatistics& s);

}  // namespace vknerf::cli

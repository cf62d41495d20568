// vknerf command line. Exit codes: 0 success, 1 runtime error, 2 usage error, 128 + N when stopped
// by signal N (train saves first: 130 for SIGINT, 143 for SIGTERM).
#include <cstdio>
#include <exception>
#include <map>
#include <sstream>

#include "checks.h"
#include "command.h"
#include "lib/process/subprocess.h"
#include "progress.h"
#include "vknerf/error.h"
#include "vknerf/file_output.h"

namespace vknerf::cli {

std::vector<Command>& commands() {
  static std::vector<Command> all;
  return all;
}

Registration::Registration(std::string path, std::string help, Setup setup) {
  commands().push_back({std::move(path), std::move(help), std::move(setup)});
}

std::shared_ptr<Context> Globals::context() const {
  // Initialised in one expression: its destructor is then registered after the driver and layers
  // the creation loads have registered theirs, so it runs before theirs at exit.
  static std::shared_ptr<Context> ctx = [this] {
    auto created = Context::create({device, validation});
    std::fprintf(stderr, "vknerf: device %s\n", created->describe().c_str());
    created->setCompileProgress(compileProgressPrinter());
    return created;
  }();
  return ctx;
}

namespace {

// CLI11 answers a misspelt command with "A subcommand is required": name the word and the commands
// it could have been instead. True when that was the error (and it has been printed).
bool reportUnknownCommand(CLI::App& app) {
  const std::function<bool(CLI::App*)> any = [](CLI::App*) { return true; };
  CLI::App* level = &app;
  for (bool deeper = true; deeper;) {
    deeper = false;
    for (CLI::App* sub : level->get_subcommands(any))
      if (sub->parsed()) level = sub, deeper = true;
  }
  if (level->get_subcommands(any).empty()) return false;  // a command, not a group of them
  const auto rest = level->remaining();
  if (rest.empty() || rest.front().empty() || rest.front()[0] == '-') return false;
  std::string names;
  for (CLI::App* sub : level->get_subcommands(any)) names += (names.empty() ? "" : ", ") + sub->get_name();
  std::fprintf(stderr, "vknerf: unknown command '%s' (commands: %s)\n", rest.front().c_str(), names.c_str());
  return true;
}

}  // namespace
}  // namespace vknerf::cli

int main(int argc, char** argv) {
  using namespace vknerf::cli;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress lines reach a log file as they happen
  CLI::App app{"vknerf: Neural Radiance Fields on Vulkan compute shaders"};
  app.require_subcommand(1);
  Globals globals;
  app.add_option("--device", globals.device, "Vulkan device: index or name substring (default: $VKNERF_DEVICE, else the best)");
  app.add_flag("--validation", globals.validation, "Enable the Khronos validation layer");

  // Build the command tree; "bench mlp" nests under "bench".
  std::map<std::string, CLI::App*> nodes;
  std::function<int()> action;
  std::vector<std::pair<CLI::App*, std::function<int()>>> actions;
  for (auto& cmd : commands()) {
    CLI::App* parent = &app;
    std::istringstream words(cmd.path);
    std::string word, prefix;
    std::vector<std::string> parts;
    while (words >> word) parts.push_back(word);
    for (size_t i = 0; i + 1 < parts.size(); ++i) {
      prefix += (prefix.empty() ? "" : " ") + parts[i];
      auto it = nodes.find(prefix);
      if (it == nodes.end()) {
        CLI::App* sub = parent->add_subcommand(parts[i], parts[i] + " commands");
        sub->require_subcommand(1);
        it = nodes.emplace(prefix, sub).first;
      }
      parent = it->second;
    }
    CLI::App* sub = parent->add_subcommand(parts.back(), cmd.help);
    nodes[cmd.path] = sub;
    actions.emplace_back(sub, cmd.setup(*sub, globals));
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (reportUnknownCommand(app)) return 2;
    int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  // An empty value (`-o ''`) names no file and no choice: a command would take it for an option not
  // given, or fail at the end with no name to show. A usage error naming the flag, before any work.
  for (size_t i = 0; i < actions.size(); ++i) {
    if (!actions[i].first->parsed()) continue;
    for (const CLI::Option* opt : actions[i].first->get_options()) {
      if (opt->count() == 0 || opt->get_expected_max() == 0) continue;  // not given, or a switch
      for (const std::string& value : opt->results())
        if (value.empty()) {
          std::fprintf(stderr, "vknerf: %s: %s was given an empty value\n", commands()[i].path.c_str(),
                       opt->get_name(false, true).c_str());
          return 2;
        }
    }
  }
  // Ctrl-C or a kill during any command leaves no temporary file behind (train saves first).
  vknerf::removeTemporaryFilesOnSignals();
  try {
    for (auto& [sub, act] : actions)
      if (sub->parsed()) return act();
  } catch (const UsageError& e) {
    std::fprintf(stderr, "vknerf: %s\n", e.what());
    return 2;
  } catch (const vknerf::process::Stopped& e) {
    // A signal passed on to a child (COLMAP, ffmpeg): the child has ended, the run's files are gone.
    std::fprintf(stderr, "vknerf: %s\n", e.what());
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vknerf: error: %s\n", e.what());
    return 1;
  }
  return 2;
}

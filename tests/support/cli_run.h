#pragma once
// Running the built vknerf command line from a test: exit code and combined output.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

#include "support/temp_dir.h"

namespace vknerf::test {

struct CliResult {
  int code = -1;
  std::string output;
};

// `args` is appended to the binary's path and run by the shell, stdout and stderr together;
// `env` ("NAME=value ...") is set for that command.
inline CliResult runCli(const std::string& args, const std::string& env = "") {
  std::string cmd = env + (env.empty() ? "" : " ") + std::string(VKNERF_BINARY_DIR) + "/vknerf " + args + " 2>&1";
  CliResult r;
  FILE* p = popen(cmd.c_str(), "r");
  std::array<char, 512> buf;
  while (p && fgets(buf.data(), buf.size(), p)) r.output += buf.data();
  int status = p ? pclose(p) : -1;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  // ctest's VKNERF_VALIDATION=1 reaches the command line too: any layer message fails the test.
  if (r.output.find("vknerf: validation") != std::string::npos)
    ADD_FAILURE() << "validation messages from: vknerf " << args << "\n" << r.output;
  return r;
}

// A shell fragment that waits until `condition` (a shell command) succeeds, polling every 0.1 s
// for at most 2 minutes: for a test that signals a command it started in the background once
// that command has reached a given point.
inline std::string shellWaitUntil(const std::string& condition) {
  return "for i in $(seq 1200); do " + condition + " && break; sleep 0.1; done; ";
}

inline std::string scene() { return std::string(VKNERF_SOURCE_DIR) + "/assets/tabletop"; }

// A path in a temporary folder of this test process, removed when it exits.
inline std::string temp(const std::string& name) {
  static const TempDir dir("cli");
  return dir.file(name);
}

}  // namespace vknerf::test

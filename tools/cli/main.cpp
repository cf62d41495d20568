// vknerf command line. Exit codes: 0 success, 1 runtime error, 2 usage error.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "vknerf/context.h"
#include "vknerf/error.h"

int main(int argc, char** argv) {
  CLI::App app{"vknerf: Neural Radiance Fields on Vulkan compute"};
  app.require_subcommand(1);
  std::string device;
  app.add_option("--device", device, "Vulkan device: index or name substring (default: VKNERF_DEVICE, else best)");

  auto* info = app.add_subcommand("info", "List Vulkan devices and show the one vknerf picks");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  try {
    if (*info) {
      for (const auto& d : vknerf::Context::listDevices())
        std::printf("device %u: %s%s\n", d.index, d.name.c_str(), d.usable ? "" : " (unusable: no Vulkan 1.2 compute)");
      auto ctx = vknerf::Context::create({device, false});
      std::printf("using: %s\n", ctx->describe().c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "vknerf: error: %s\n", e.what());
    return 1;
  }
  return 0;
}

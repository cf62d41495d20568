// `vknerf info`: the Vulkan devices and the one vknerf picks.
#include <cstdio>
#include <string>

#include "command.h"

namespace vknerf::cli {
namespace {

Registration info("info", "List Vulkan devices and show the one vknerf picks", [](CLI::App&, const Globals& g) {
  return [&g] {
    for (const auto& d : Context::listDevices())
      std::printf("device %u: %s%s\n", d.index, d.name.c_str(), d.usable ? "" : " (unusable: no Vulkan 1.2 compute)");
    std::printf("using: %s\n", g.context()->describe().c_str());
    for (const auto& line : g.context()->capabilities()) std::printf("  %s\n", line.c_str());
    std::string names;
    for (const auto& n : Context::profileNames()) names += (names.empty() ? "" : ", ") + n;
    std::printf("device profiles (VKNERF_DEVICE_PROFILE=NAME): %s\n", names.c_str());
    return 0;
  };
});

}  // namespace
}  // namespace vknerf::cli

// `vknerf selfcheck`: render an analytic scene through every rendering kernel and compare it with
// the CPU reference; exit 1 if they disagree.
#include <cstdio>

#include "command.h"
#include "kernels/selfcheck.h"

namespace vknerf::cli {
namespace {

struct Options {
  uint32_t size = 64, coarse = 64, fine = 64;
};

Registration selfcheck("selfcheck", "Render an analytic scene on the device and compare with the CPU reference",
                       [](CLI::App& app, const Globals& g) {
                         auto o = std::make_shared<Options>();
                         app.add_option("--size", o->size, "Image width and height")->check(CLI::Range(1u, 1024u));
                         app.add_option("--coarse", o->coarse, "Stratified samples per ray")->check(CLI::Range(1u, 1024u));
                         app.add_option("--fine", o->fine, "Importance samples per ray")->check(CLI::Range(0u, 1024u));
                         return [o, &g] {
                           auto r = nerf::selfCheck(*g.context(), o->size, o->coarse, o->fine);
                           for (auto& [name, ms] : r.kernelMilliseconds) std::printf("  %-18s %8.3f ms\n", name.c_str(), ms);
                           std::printf("max |error| vs CPU reference: colour %.2e, opacity %.2e, depth %.2e\n",
                                       r.maxColorError, r.maxOpacityError, r.maxDepthError);
                           bool ok = r.maxColorError < 2e-4 && r.maxOpacityError < 2e-4 && r.maxDepthError < 2e-3;  // bounds of tests/cli/test_selfcheck.cpp
                           std::printf("selfcheck: %s\n", ok ? "ok" : "FAILED");
                           return ok ? 0 : 1;
                         };
                       });

}  // namespace
}  // namespace vknerf::cli

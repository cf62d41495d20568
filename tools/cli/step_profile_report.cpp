#include "step_profile_report.h"

#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace vknerf::cli {
namespace {

// A kernel recorded several times in one submission (chunks, levels) is one row: its total.
std::vector<std::pair<std::string, double>> merged(const std::vector<std::pair<std::string, double>>& kernels) {
  std::vector<std::pair<std::string, double>> rows;
  std::map<std::string, size_t> at;
  for (const auto& [name, ms] : kernels) {
    auto [it, fresh] = at.emplace(name, rows.size());
    if (fresh) rows.emplace_back(name, 0.0);
    rows[it->second].second += ms;
  }
  return rows;
}

}  // namespace

void printStepProfile(const StepProfile& p) {
  const double wall = p.wallMs > 0 ? p.wallMs : 1.0;
  auto pct = [&](double ms) { return 100.0 * ms / wall; };
  double host = p.hostAfterMs, kernels = 0, gaps = 0;
  std::printf("the last step: %.2f ms wall, %zu submission(s)\n", p.wallMs, p.submissions.size());
  for (size_t i = 0; i < p.submissions.size(); ++i) {
    const auto& s = p.submissions[i];
    double device = 0;
    for (const auto& k : s.kernels) device += k.second;
    host += s.hostBeforeMs;
    kernels += device;
    gaps += s.waitMs - device;
    std::printf("  host before submission %zu %20s %8.2f ms  %5.1f%%\n", i + 1, "", s.hostBeforeMs, pct(s.hostBeforeMs));
    std::printf("  submission %zu: waited %.2f ms (kernels %.2f ms, dispatch gaps %.2f ms)\n", i + 1, s.waitMs, device,
                s.waitMs - device);
    for (const auto& [name, ms] : merged(s.kernels))
      std::printf("    %-40s %8.2f ms  %5.1f%%\n", name.c_str(), ms, pct(ms));
  }
  std::printf("  host after the last submission %14s %8.2f ms  %5.1f%%\n", "", p.hostAfterMs, pct(p.hostAfterMs));
  std::printf("  in all: kernels %.2f ms (%.1f%%), dispatch gaps %.2f ms (%.1f%%), host %.2f ms (%.1f%%)\n", kernels,
              pct(kernels), gaps, pct(gaps), host, pct(host));
}

}  // namespace vknerf::cli

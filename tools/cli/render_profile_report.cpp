#include "render_profile_report.h"

#include <algorithm>
#include <cstdio>

namespace vknerf::cli {

void addRenderProfileOption(CLI::App& app, bool& profile, const std::string& more) {
  app.add_flag("--profile", profile,
               "Time each kernel of the renders on the device and print where a view's time goes (device ms a view "
               "per kernel" + more + ")");
}

nlohmann::json printKernelProfile(const KernelTimes& summed, size_t views, double seconds) {
  nlohmann::json out = nlohmann::json::object();
  if (summed.empty()) {
    std::printf("--profile: this device's compute queue has no timestamps; no kernel was timed\n");
    return out;
  }
  KernelTimes rows = summed;
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  double kernels = 0;
  for (auto& row : rows) kernels += (row.second /= double(views));
  const double wallMs = 1000.0 * seconds / double(views);
  std::printf("where a view's time goes (device ms a view, the mean over %zu): kernels %.1f of %.1f ms wall\n", views,
              kernels, wallMs);
  for (const auto& [name, ms] : rows) {
    std::printf("  %-36s %9.1f ms  %5.1f%%\n", name.c_str(), ms, 100.0 * ms / std::max(wallMs, 1e-9));
    out[name] = ms;
  }
  return out;
}

}  // namespace vknerf::cli

#include "step_profile_report.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace vknerf::cli {
namespace {

// A kernel recorded several times in one submission (chunks, levels) is one row: its total.
std::vector<std::pair<std::string, double>> merged(const std::vector<std::pair<std::string, double>>& kernels) {
  std::vector<std::pair<std::string, double>> rows;
  addKernelTimes(rows, kernels);
  return rows;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// One step's figures, each a number the report takes the median of.
struct StepFigures {
  double wall = 0, host = 0, kernels = 0, gaps = 0;
  std::vector<double> hostBefore, wait, device;      // per submission
  std::vector<std::vector<std::pair<std::string, double>>> named;  // per submission: ms per kernel, in order
};

StepFigures figuresOf(const StepProfile& p) {
  StepFigures f;
  f.wall = p.wallMs;
  f.host = p.hostAfterMs;
  for (const auto& s : p.submissions) {
    double device = 0;
    f.named.emplace_back();
    f.named.back() = merged(s.kernels);
    for (const auto& row : f.named.back()) device += row.second;
    f.hostBefore.push_back(s.hostBeforeMs);
    f.wait.push_back(s.waitMs);
    f.device.push_back(device);
    f.host += s.hostBeforeMs;
    f.kernels += device;
    f.gaps += s.waitMs - device;
  }
  return f;
}

template <class Get>
double medianOf(const std::vector<StepFigures>& steps, Get get) {
  std::vector<double> v;
  for (const auto& s : steps) v.push_back(get(s));
  return median(v);
}

}  // namespace

void printStepProfile(const std::vector<StepProfile>& profiles) {
  if (profiles.empty()) return;
  // The submissions are reported one by one over the steps shaped as the last one (a step that
  // updates the occupancy grid, say, may submit differently); the totals over every step.
  std::vector<StepFigures> all, shaped;
  for (const auto& p : profiles) all.push_back(figuresOf(p));
  for (const auto& f : all)
    if (f.wait.size() == all.back().wait.size()) shaped.push_back(f);
  const size_t K = all.size(), submissions = all.back().wait.size();
  const double wall = std::max(medianOf(all, [](const StepFigures& f) { return f.wall; }), 1e-9);
  auto pct = [&](double ms) { return 100.0 * ms / wall; };
  if (K == 1)
    std::printf("the last step: %.2f ms wall, %zu submission(s)\n", wall, submissions);
  else
    std::printf("the last %zu steps, each figure its median over them: %.2f ms wall, %zu submission(s)\n", K, wall,
                submissions);
  for (size_t i = 0; i < submissions; ++i) {
    const double before = medianOf(shaped, [i](const StepFigures& f) { return f.hostBefore[i]; });
    const double wait = medianOf(shaped, [i](const StepFigures& f) { return f.wait[i]; });
    const double device = medianOf(shaped, [i](const StepFigures& f) { return f.device[i]; });
    std::printf("  host before submission %zu %20s %8.2f ms  %5.1f%%\n", i + 1, "", before, pct(before));
    std::printf("  submission %zu: waited %.2f ms (kernels %.2f ms, dispatch gaps %.2f ms)\n", i + 1, wait, device,
                medianOf(shaped, [i](const StepFigures& f) { return f.wait[i] - f.device[i]; }));
    // Every kernel any of these steps ran, in the order of the step that ran most of them; a kernel
    // some steps did not run (the occupancy update) is the median over those that did.
    const StepFigures* widest = &shaped.back();
    for (const auto& f : shaped)
      if (f.named[i].size() > widest->named[i].size()) widest = &f;
    for (const auto& kernel : widest->named[i]) {
      const std::string& name = kernel.first;
      std::vector<double> v;
      for (const auto& f : shaped)
        for (const auto& row : f.named[i])
          if (row.first == name) v.push_back(row.second);
      const double ms = median(v);
      if (v.size() == shaped.size())
        std::printf("    %-40s %8.2f ms  %5.1f%%\n", name.c_str(), ms, pct(ms));
      else
        std::printf("    %-40s %8.2f ms  %5.1f%%  (in %zu of %zu steps)\n", name.c_str(), ms, pct(ms), v.size(),
                    shaped.size());
    }
  }
  const double after = medianOf(all, [](const StepFigures& f) {
    double before = 0;
    for (double b : f.hostBefore) before += b;
    return f.host - before;
  });
  std::printf("  host after the last submission %14s %8.2f ms  %5.1f%%\n", "", after, pct(after));
  const double kernels = medianOf(all, [](const StepFigures& f) { return f.kernels; });
  const double gaps = medianOf(all, [](const StepFigures& f) { return f.gaps; });
  const double host = medianOf(all, [](const StepFigures& f) { return f.host; });
  std::printf("  in all: kernels %.2f ms (%.1f%%), dispatch gaps %.2f ms (%.1f%%), host %.2f ms (%.1f%%)\n", kernels,
              pct(kernels), gaps, pct(gaps), host, pct(host));
}

}  // namespace vknerf::cli

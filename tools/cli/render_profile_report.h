#pragma once
// `--profile` of the commands that render a loaded model (eval, render): every kernel of the views
// timed on the device (RenderSettings::profile) and printed as device ms a view, largest first.
#include <CLI/CLI.hpp>

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "vknerf/kernel_times.h"

namespace vknerf::cli {

// `more`: the rest of the help's last sentence, where the command reports the times elsewhere too.
void addRenderProfileOption(CLI::App& app, bool& profile, const std::string& more = "");

// `summed`: the views' kernel times added by name; `seconds`: their wall time together. Prints
// each kernel's mean a view and its share of a view's wall time (or one line saying the device
// has no timestamps) and returns the rows (name: ms a view) for a JSON report.
nlohmann::json printKernelProfile(const KernelTimes& summed, size_t views, double seconds);

}  // namespace vknerf::cli

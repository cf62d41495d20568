#pragma once
// `--appearance I` of the commands that render a loaded model (render, eval): which training
// photo's appearance vector a model trained with --appearance-dims renders with; without it, the
// mean of the photos' vectors (RenderSettings::appearancePhoto).
#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>

namespace vknerf::cli {

inline void addAppearanceOption(CLI::App& app, std::optional<uint32_t>& photo) {
  app.add_option("--appearance", photo,
                 "fast, trained with --appearance-dims: render with training photo I's appearance (exposure, white "
                 "balance; I counts the training split from 0; default: the mean of the photos')");
}

}  // namespace vknerf::cli

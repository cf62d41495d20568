#pragma once
// The RenderSettings flags of the commands that render a loaded model (render, eval):
// `--appearance I`, which training photo's appearance vector a model trained with --appearance-dims
// renders with (without it, the mean of the photos' vectors), and `--min-transmittance T`, where a
// ray of the fast model stops.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "checks.h"
#include "vknerf/model.h"

namespace vknerf::cli {

// Model::load with RenderSettings::appearancePhoto from --appearance: a photo past the model's
// training photos is the flag out of range, a usage error naming it (exit 2), not a runtime error.
inline Model loadForAppearance(const std::shared_ptr<Context>& ctx, const std::string& path, const RenderSettings& settings,
                               const std::string& command) {
  try {
    return Model::load(ctx, path, settings);
  } catch (const Error& e) {
    // The appearance embedding's own words (src/models/common/appearance.cpp).
    const std::string prefix = "render settings: appearance photo ", what = e.what();
    if (!settings.appearancePhoto || what.rfind(prefix, 0) != 0) throw;
    throw UsageError(command + ": --appearance " + std::to_string(*settings.appearancePhoto) + " is out of range:" +
                     what.substr(what.find(", but") + 5));
  }
}

inline void addAppearanceOption(CLI::App& app, std::optional<uint32_t>& photo) {
  app.add_option("--appearance", photo,
                 "fast, trained with --appearance-dims: render with training photo I's appearance (exposure, white "
                 "balance; I counts the training split from 0; default: the mean of the photos')");
}

inline void addMinTransmittanceOption(CLI::App& app, float& minTransmittance) {
  char fallback[32];
  std::snprintf(fallback, sizeof fallback, "%g", double(RenderSettings{}.minTransmittance));
  app.add_option("--min-transmittance", minTransmittance,
                 "fast: a ray stops once its transmittance is below this, what lies behind then adding at most that "
                 "share of the pixel (default " + std::string(fallback) +
                     ", as training stops; larger renders faster; 0 shades every sample the march finds)")
      ->check(UnitFraction);
}

}  // namespace vknerf::cli

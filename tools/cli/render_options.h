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

// Model::load with the RenderSettings of these flags, each a usage error naming it (exit 2), not a
// runtime error, where the model makes it wrong or void: --appearance past the model's training
// photos, and --min-transmittance (given: `minTransmittanceGiven`) on a vanilla model, whose rays
// take a fixed count of samples and never stop early, so the flag would change nothing.
inline Model loadWithRenderSettings(const std::shared_ptr<Context>& ctx, const std::string& path,
                                    const RenderSettings& settings, bool minTransmittanceGiven,
                                    const std::string& command) {
  std::optional<Model> model;
  try {
    model.emplace(Model::load(ctx, path, settings));
  } catch (const Error& e) {
    // The appearance embedding's own words (src/models/common/appearance.cpp).
    const std::string prefix = "render settings: appearance photo ", what = e.what();
    if (!settings.appearancePhoto || what.rfind(prefix, 0) != 0) throw;
    throw UsageError(command + ": --appearance " + std::to_string(*settings.appearancePhoto) + " is out of range:" +
                     what.substr(what.find(", but") + 5));
  }
  if (minTransmittanceGiven && !model->config().isFast())
    throw UsageError(command + ": --min-transmittance has no effect on " + path +
                     ", a vanilla model (its rays take a fixed count of samples; drop the flag)");
  return std::move(*model);
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

#pragma once
// The RenderSettings flags of the commands that render a loaded model (render, eval):
// `--appearance I`, which training photo's appearance vector a model trained with --appearance-dims
// renders with (without it, the mean of the photos' vectors), `--min-transmittance T`, where a
// ray of the fast model stops, and `--proposal-samples N`, the field samples a ray its proposal places.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "checks.h"
#include "vknerf/model.h"

namespace vknerf::cli {

// Which of the sampling flags the command line gave (their values are in RenderSettings).
struct GivenRenderFlags {
  bool minTransmittance = false, proposalSamples = false;
  static GivenRenderFlags of(const CLI::App& app) {
    return {app.count("--min-transmittance") > 0, app.count("--proposal-samples") > 0};
  }
};

// Model::load with the RenderSettings of these flags, each a usage error naming it (exit 2), not a
// runtime error, where the model makes it wrong or void: --appearance past the model's training
// photos, --min-transmittance on a vanilla model, whose rays take a fixed count of samples and
// never stop early, and --proposal-samples on a model without a proposal: the flag would change
// nothing.
inline Model loadWithRenderSettings(const std::shared_ptr<Context>& ctx, const std::string& path,
                                    const RenderSettings& settings, GivenRenderFlags given,
                                    const std::string& command) {
  std::optional<Model> model;
  try {
    model.emplace(Model::load(ctx, path, settings));
  } catch (const Error& e) {
    const std::string what = e.what();
    // src/models/field_pipeline.cpp's words.
    if (given.proposalSamples && what.rfind("render settings: proposal samples", 0) == 0)
      throw UsageError(command + ": --proposal-samples has no effect on " + path +
                       ", whose rays are not sampled by a proposal (drop the flag)");
    // The appearance embedding's own words (src/models/common/appearance.cpp).
    const std::string prefix = "render settings: appearance photo ";
    if (!settings.appearancePhoto || what.rfind(prefix, 0) != 0) throw;
    throw UsageError(command + ": --appearance " + std::to_string(*settings.appearancePhoto) + " is out of range:" +
                     what.substr(what.find(", but") + 5));
  }
  if (given.minTransmittance && !model->config().isFast())
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

inline void addProposalSamplesOption(CLI::App& app, uint32_t& samples) {
  app.add_option("--proposal-samples", samples,
                 "fast, sampled by a proposal: the field samples a ray its proposal places (default: as trained; "
                 "fewer render faster, each standing for more of the ray's weight)")
      ->check(CLI::Range(1u, FastModel::kMaxProposalSamples));
}

}  // namespace vknerf::cli

// TrainConfig::validate: one check of a configuration's fields, for flags and checkpoints alike.
// Field names are the checkpoint's keys (src/io/checkpoint/config_json.cpp), so a message points into the file.
#include <cmath>
#include <cstdio>
#include <variant>
#include <string>

#include "vknerf/config.h"
#include "vknerf/error.h"

namespace vknerf {
namespace {

std::string text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

void inRange(const char* field, uint64_t v, uint64_t lo, uint64_t hi) {
  if (v < lo || v > hi)
    throw Error(std::string(field) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                std::to_string(v));
}

// Open at `lo` when `openLow`: learning rates and epsilon must be > 0, betas may be 0.
void inRange(const char* field, float v, double lo, double hi, bool openLow) {
  if (!std::isfinite(v) || (openLow ? !(v > lo) : !(v >= lo)) || !(v < hi))
    throw Error(std::string(field) + " must be finite and in " + (openLow ? "(" : "[") + text(lo) + ", " + text(hi) +
                "), got " + text(v));
}

void density(const char* field, DensityActivation d) {
  if (uint32_t(d) > uint32_t(DensityActivation::Softplus))
    throw Error(std::string(field) + " is not a known activation (0 relu, 1 trunc_exp, 2 softplus), got " +
                std::to_string(uint32_t(d)));
}

void validateModel(const VanillaModel& m) {
  inRange("model.width", m.width, 8, 4096);
  if (m.width % 8) throw Error("model.width must be a multiple of 8, got " + std::to_string(m.width));
  inRange("model.depth", m.depth, 1, 64);
  if (m.skipLayer >= m.depth)
    throw Error("model.skip_layer must be below model.depth (" + std::to_string(m.depth) + "), got " +
                std::to_string(m.skipLayer));
  inRange("model.pos_levels", m.posLevels, 1, 32);
  inRange("model.dir_levels", m.dirLevels, 1, 32);
  density("model.density", m.density);
  inRange("model.coarse_samples", m.coarseSamples, 1, 4096);
  inRange("model.fine_samples", m.fineSamples, 0, 4096);
}

void validateModel(const FastModel& m) {
  inRange("model.width", m.width, 8, 4096);
  if (m.width % 8) throw Error("model.width must be a multiple of 8, got " + std::to_string(m.width));
  inRange("model.depth", m.depth, 1, 64);
  if (m.featureWidth != 0) {
    inRange("model.feature_width", m.featureWidth, 4, m.width);
    if (m.featureWidth % 4)
      throw Error("model.feature_width must be a multiple of 4, got " + std::to_string(m.featureWidth));
  }
  density("model.density", m.density);
  inRange("model.hash_levels", m.hashLevels, 1, 32);
  inRange("model.hash_features", m.hashFeatures, 1, 8);
  // 0: from the dataset (src/models/fast/fast_capacity.h)
  if (m.hashLog2Size != 0) inRange("model.hash_log2_size", m.hashLog2Size, 2, 26);
  inRange("model.hash_base_resolution", m.hashBaseResolution, 1, 65536);
  if (m.hashGrowth != 0) inRange("model.hash_growth", m.hashGrowth, 1.0, 16.0, false);
  inRange("model.sh_degree", m.shDegree, 1, 8);
  inRange("model.grid_resolution", m.gridResolution, 1, 256);
  inRange("model.cascades", m.cascades, 0, 8);
  inRange("model.cone_angle", m.coneAngle, 0.0, 1.0, false);
  inRange("model.near_distance", m.nearDistance, 0.0, 1e30, false);
  inRange("model.march_steps", m.marchSteps, 1, 65536);
  inRange("model.max_samples_per_ray", m.maxSamplesPerRay, 1, 65536);
  inRange("samples_per_batch", m.samplesPerBatch, 1, 1u << 28);
  inRange("grid_update_interval", m.gridUpdateInterval, 1, UINT32_MAX);
  inRange("hash_lr_scale", m.hashLearningRateScale, 0.0, 1e6, true);
  inRange("distortion_loss", m.distortionLoss, 0.0, 1e3, false);
  inRange("model.far_field", uint32_t(m.farField), 0, uint32_t(FarField::Learned));
}

}  // namespace

void TrainConfig::validate() const {
  std::visit([](const auto& m) { validateModel(m); }, model);
  inRange("rays_per_batch", raysPerBatch, 1, 1u << 26);
  inRange("lr", learningRate, 0.0, 1e3, true);
  inRange("lr_final", learningRateFinal, 0.0, 1e3, true);
  inRange("decay_steps", decaySteps, 1, UINT32_MAX);
  inRange("beta1", beta1, 0.0, 1.0, false);
  inRange("beta2", beta2, 0.0, 1.0, false);
  inRange("epsilon", epsilon, 0.0, 1.0, true);
  for (float b : background) inRange("background", b, 0.0, 1.0 + 1e-6, false);
}

}  // namespace vknerf

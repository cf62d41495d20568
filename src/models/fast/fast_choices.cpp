#include "models/fast/fast_choices.h"

#include <cmath>
#include <cstdio>

#include "models/fast/fast_capacity.h"
#include "vknerf/error.h"

namespace vknerf::models {

uint32_t cascadesFor(float aabbScale) {
  uint32_t c = 1;
  constexpr uint32_t kMaxCascades = 8;  // as TrainConfig::validate allows
  while (c < kMaxCascades && std::ldexp(1.0f, int(c - 1)) < aabbScale) ++c;
  return c;
}

float occupancyThresholdOf(const FastModel& model) {
  if (model.occupancyThreshold > 0) return model.occupancyThreshold;
  return model.usesProposal() ? 0.001f : 0.01f;  // docs/real_captures.md, "The proposal at equal time"
}

Sampler samplerFor(bool transparentPixels) { return transparentPixels ? Sampler::March : Sampler::Proposal; }

std::string chooseFastModel(FastModel& model, const Dataset& train, bool cpuDevice, bool transparentPixels) {
  if (model.cascades == 0) model.cascades = cascadesFor(train.aabbScale);
  // First: the capacity and the occupancy threshold follow the sampler.
  std::string samplerNote;
  if (model.sampler == Sampler::Auto) {
    model.sampler = model.proposalSamples ? samplerFor(transparentPixels) : Sampler::March;
    samplerNote = model.usesProposal() ? "sampler: " + std::to_string(model.proposalSamples) +
                                             " samples a ray placed by a proposal (the photos have no alpha)"
                  : transparentPixels ? "sampler: the march (the photos have alpha: short rays, nothing for a proposal to save)"
                                      : "sampler: the march (no proposal samples asked for)";
  }
  // A march's model holds no proposal samples, so that its checkpoint reads as the march also to a
  // build from before the sampler's key (which took proposal_samples > 0 for the proposal).
  if (model.sampler == Sampler::March) model.proposalSamples = 0;
  std::string note = resolveFastCapacity(model, train, cpuDevice);
  if (!samplerNote.empty()) note = samplerNote + (note.empty() ? "" : "\n") + note;
  if (model.occupancyThreshold == 0) {
    model.occupancyThreshold = occupancyThresholdOf(model);
    if (model.usesProposal()) {
      char why[96];
      std::snprintf(why, sizeof why, "occupancy threshold: %g (the proposal's candidates reach faint cells)",
                    double(model.occupancyThreshold));
      note += std::string(note.empty() ? "" : "\n") + why;
    }
  }
  // Photos without alpha leave what lies behind the scene box to the model: a learned far field.
  if (model.farField == FarField::Auto) {
    model.farField = transparentPixels ? FarField::Constant : FarField::Learned;
    note += std::string(note.empty() ? "" : "\n") + "far field: " +
            (transparentPixels ? "constant (the photos have alpha)" : "learned (the photos have no alpha)");
  }
  // Where a photo is transparent its target is composited over the background: a learned one would
  // be fitted to itself there.
  if (model.farField == FarField::Learned && transparentPixels)
    throw Error("model.far_field learned needs opaque photos, and some training pixel has alpha < 255 "
                "(use the far field auto or constant)");
  return note;
}

}  // namespace vknerf::models

#pragma once
// What the fast model decides for itself from the training set, where its configuration leaves a
// choice open: the occupancy cascades from the scene's aabb_scale, the sampler and the far field
// from whether the photos have alpha, the capacity (fast_capacity.h) and the occupancy threshold
// from the sampler. The Trainer calls it once, before the model is built; the model's configuration
// then holds every choice, so a checkpoint records them.
#include <string>

#include "vknerf/config.h"
#include "vknerf/dataset.h"

namespace vknerf::models {

// instant-ngp's cascades for an aabb_scale: enough doublings of the inner cube to reach the box.
uint32_t cascadesFor(float aabbScale);

// The occupancy threshold (FastModel::occupancyThreshold) a model trains with: its own, or where
// it is open (0) instant-ngp's 0.01 for the march and 0.001 with the proposal estimator.
float occupancyThresholdOf(const FastModel& model);

// The sampler an open one (Sampler::Auto) becomes: the proposal for opaque photos, the march where
// some pixel has alpha (an object's rays there are short: docs/real_captures.md, "The proposal by
// default").
Sampler samplerFor(bool transparentPixels);

// Fills what `model` leaves open; `transparentPixels`: some training pixel has alpha < 255.
// Returns the lines that say what was chosen and why (empty when nothing was open). Throws
// vknerf::Error for a learned far field over transparent photos.
std::string chooseFastModel(FastModel& model, const Dataset& train, bool cpuDevice, bool transparentPixels);

}  // namespace vknerf::models

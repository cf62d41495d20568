#pragma once
// The proposal estimator's density field (Sampler::Proposal): the fast field's parts at a
// small size, evaluated at every sample the march finds, its density alone read (nerfacto's
// proposal network: a hash grid of a few levels and one layer 16 wide). Its checkpoint arrays are
// "proposal.encoding.*" and "proposal.mlp.*".
#include <cstdint>

#include "models/fast/fast_field.h"
#include "vknerf/config.h"

namespace vknerf::models {

// The proposal's own configuration: the field's with proposalLevels levels of 2 features in tables
// of at most 2^17 entries, and a network of one layer 16 wide over first-degree harmonics.
TrainConfig proposalConfigOf(const TrainConfig& config);

// How far the proposal's weights place a training step's samples (ProposalSampler::Draws::anneal):
// nerfacto's schedule, a = 10 x / (9 x + 1) of x = step / proposalAnnealSteps (clamped at 1), from
// uniform by length at the first step (the proposal knows nothing yet) to its weights; 1 with no
// annealing steps.
float proposalAnneal(const FastModel& model, uint32_t step);

// What the proposal's checkpoint arrays' names begin with (FastField's stateName).
inline constexpr const char* kProposalStateName = "proposal.";

}  // namespace vknerf::models

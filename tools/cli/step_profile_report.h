#pragma once
// `vknerf train --profile`: where a step's wall time went, submission by submission, so that every
// millisecond is attributed to a kernel, to the host or to the gaps inside a submission. Over the
// last K steps (--profile-steps), each figure is its median over them: one step's figures move by
// tens of per cent on a shared machine, their medians much less.
#include <vector>

#include "vknerf/trainer.h"

namespace vknerf::cli {

// `steps`: the profiles of the last steps, oldest first (at least one).
void printStepProfile(const std::vector<StepProfile>& steps);

}  // namespace vknerf::cli

#pragma once
// `vknerf train --profile`: the last step's wall time, submission by submission, so that every
// millisecond is attributed to a kernel, to the host or to the gaps inside a submission.
#include "vknerf/trainer.h"

namespace vknerf::cli {

void printStepProfile(const StepProfile& profile);

}  // namespace vknerf::cli

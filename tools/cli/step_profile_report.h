#pragma once
// `vknerf train --profile`: where a step's wall time went, submission by submission, so that every
// millisecond is attributed to a kernel, to the host or to the gaps inside a submission. Over the
// last K steps (--profile-steps), each figure is its median over them: one step's figures move by
// tens of per cent on a shared machine, their medians much less.
#include <string>
#include <utility>
#include <vector>

#include "vknerf/trainer.h"

namespace vknerf::cli {

// `steps`: the profiles of the last steps, oldest first (at least one).
void printStepProfile(const std::vector<StepProfile>& steps);

// Kernel times (name, ms) added into `sums` by name: a kernel's rows become one, in the order each
// name first came (a step's chunks and levels; eval --profile's views).
void addKernelTimes(std::vector<std::pair<std::string, double>>& sums,
                    const std::vector<std::pair<std::string, double>>& add);

}  // namespace vknerf::cli

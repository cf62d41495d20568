#pragma once
// Device milliseconds per kernel, as the profiles report them (RenderedImage::kernelMs, a training
// step's StepProfile): one (name, ms) row per kernel, in the order each was first recorded.
#include <string>
#include <utility>
#include <vector>

namespace vknerf {

using KernelTimes = std::vector<std::pair<std::string, double>>;

// `add` summed into `sums` by name: a name already there gains its time, a new one is appended, so
// the rows of several submissions, steps or views become one row a kernel.
void addKernelTimes(KernelTimes& sums, const KernelTimes& add);

}  // namespace vknerf

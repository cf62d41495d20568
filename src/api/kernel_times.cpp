#include "vknerf/kernel_times.h"

#include <algorithm>

namespace vknerf {

void addKernelTimes(KernelTimes& sums, const KernelTimes& add) {
  for (const auto& kernel : add) {
    auto it = std::find_if(sums.begin(), sums.end(), [&](const auto& s) { return s.first == kernel.first; });
    if (it == sums.end())
      sums.push_back(kernel);
    else
      it->second += kernel.second;
  }
}

}  // namespace vknerf

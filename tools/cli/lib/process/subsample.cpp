#include "lib/process/subsample.h"

#include <cmath>

namespace vknerf::process {

std::vector<size_t> evenSubsample(size_t count, size_t keep) {
  std::vector<size_t> out;
  if (keep == 0 || keep >= count) {
    for (size_t i = 0; i < count; ++i) out.push_back(i);
    return out;
  }
  if (keep == 1) return {0};
  // i * (count - 1) / (keep - 1) rounded: steps of at least 1 since keep < count, so distinct.
  for (size_t i = 0; i < keep; ++i) out.push_back(size_t(std::llround(double(i) * double(count - 1) / double(keep - 1))));
  return out;
}

}  // namespace vknerf::process

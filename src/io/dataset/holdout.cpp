// The frames of a split: the evaluation frames a scene without a split of its own holds out.
#include <algorithm>
#include <cmath>

#include "io/dataset/dataset_loaders.h"

namespace vknerf::io::detail {

std::vector<size_t> holdoutIndices(size_t n, float fraction, const std::string& split) {
  std::vector<size_t> all(n);
  for (size_t i = 0; i < n; ++i) all[i] = i;
  if (split == "all" || n == 0) return all;
  size_t held = fraction > 0 ? std::max<size_t>(1, size_t(std::lround(double(fraction) * double(n)))) : 0;
  held = std::min(held, n);
  std::vector<bool> isHeld(n, false);
  // Evenly spaced, centred in each of `held` equal runs; distinct because n / held >= 1.
  for (size_t j = 0; j < held; ++j) isHeld[size_t((double(j) + 0.5) * double(n) / double(held))] = true;
  std::vector<size_t> out;
  bool wantHeld = split != "train";
  for (size_t i = 0; i < n; ++i)
    if (isHeld[i] == wantHeld) out.push_back(i);
  return out;
}

}  // namespace vknerf::io::detail

#pragma once
// --max-images: keeping an even spread of a long, ordered list (video frames, a photo series).
#include <cstddef>
#include <vector>

namespace vknerf::process {

// `keep` indices of 0..count-1, evenly spread and increasing, first and last included (the
// centre of each of `keep` equal runs, rounded, would drop both ends of a walk around the
// object); all of them when keep is 0 or not below count.
std::vector<size_t> evenSubsample(size_t count, size_t keep);

}  // namespace vknerf::process

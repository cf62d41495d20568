#pragma once
// The counter-based RNG of shaders/common/rng.glsl is production's (src/core/math/rng.h); the oracle
// draws its samples from the same functions.
#include "core/math/rng.h"

namespace vknerf::ref {

using core::pcgHash;
using core::rng01;
using core::rngUint;

}  // namespace vknerf::ref

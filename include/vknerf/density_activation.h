#pragma once
// How the NeRF sigma head turns its raw output x into a density. The values are fixed: saved models
// store them and the shaders receive them as they are.
//   Relu:     sigma = max(x, 0), d/dx = [x > 0] (the paper).
//   TruncExp: sigma = exp(min(x, 15)), d/dx = exp(clamp(x, -15, 15)) (instant-ngp's "truncated exp":
//             the forward is capped so sigma never overflows; the derivative is clamped the same way
//             and stays non-zero above the cap so a saturated density can still be pushed down).
//   Softplus: sigma = log(1 + exp(x)) (computed as max(x,0) + log1p(exp(-|x|))), d/dx = sigmoid(x).
#include <cstdint>

namespace vknerf {

enum class DensityActivation : uint32_t { Relu = 0, TruncExp = 1, Softplus = 2 };

}  // namespace vknerf

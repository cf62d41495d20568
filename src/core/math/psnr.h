#pragma once
// PSNR of a mean squared error: the figure training logs and evaluation report.
#include <algorithm>
#include <cmath>

namespace vknerf::core {

// PSNR of a mean squared error on [0, 1] colours. A perfect fit is reported as 100 dB (mse floored
// at 1e-10) rather than infinity, so logs and averages stay finite.
inline double psnrFromMse(double mse) { return -10.0 * std::log10(std::max(mse, 1e-10)); }

}  // namespace vknerf::core

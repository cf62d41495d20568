#pragma once
// Image-quality metrics for evaluation, on RGB images with values in [0, 1] (3 floats per pixel).
#include <cstdint>
#include <vector>

namespace vknerf::nerf {

double mse(const std::vector<float>& a, const std::vector<float>& b);
// Peak signal-to-noise ratio for a peak of 1: -10 log10(mse); capped at 100 dB for identical images.
double psnr(const std::vector<float>& a, const std::vector<float>& b);
double psnrFromMse(double mse);
// SSIM (Wang et al. 2004): 11x11 Gaussian window, sigma 1.5, K1 = 0.01, K2 = 0.03, per channel,
// averaged over the valid window positions and the channels.
double ssim(const std::vector<float>& a, const std::vector<float>& b, uint32_t width, uint32_t height);

}  // namespace vknerf::nerf

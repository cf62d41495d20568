#pragma once
// How sharp a video frame is, to keep the sharpest frame of each window (motion blur is what makes
// a video frame useless to COLMAP and to training). instant-ngp records the same score as
// `sharpness`: the variance of the Laplacian of the grey image.
#include <cstddef>
#include <vector>

#include "vknerf/dataset.h"

namespace vknerf::process {

// Variance of the 4-neighbour Laplacian (up + down + left + right - 4 * centre) of the grey image
// (0.299 R + 0.587 G + 0.114 B, 0..255) over the interior pixels; 0 for an image under 3x3.
double varianceOfLaplacian(const ImageRGBA8& image);

// The index of the highest score in each run of `window` consecutive scores (the last run may be
// shorter); the first of equal scores wins. window 0 is taken as 1.
std::vector<size_t> sharpestPerWindow(const std::vector<double>& scores, size_t window);

}  // namespace vknerf::process

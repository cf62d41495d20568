#include "lib/process/sharpness.h"

#include <algorithm>

namespace vknerf::process {

double varianceOfLaplacian(const ImageRGBA8& image) {
  const size_t w = image.width, h = image.height;
  if (w < 3 || h < 3) return 0;
  std::vector<double> grey(w * h);
  for (size_t i = 0; i < w * h; ++i) {
    const uint8_t* p = &image.rgba[4 * i];
    grey[i] = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
  }
  double sum = 0, sumSq = 0;
  for (size_t y = 1; y + 1 < h; ++y)
    for (size_t x = 1; x + 1 < w; ++x) {
      const size_t i = y * w + x;
      const double l = grey[i - w] + grey[i + w] + grey[i - 1] + grey[i + 1] - 4 * grey[i];
      sum += l;
      sumSq += l * l;
    }
  const double n = double((w - 2) * (h - 2)), mean = sum / n;
  return sumSq / n - mean * mean;
}

std::vector<size_t> sharpestPerWindow(const std::vector<double>& scores, size_t window) {
  if (window == 0) window = 1;
  std::vector<size_t> out;
  for (size_t start = 0; start < scores.size(); start += window) {
    size_t best = start;
    for (size_t i = start + 1; i < std::min(scores.size(), start + window); ++i)
      if (scores[i] > scores[best]) best = i;
    out.push_back(best);
  }
  return out;
}

}  // namespace vknerf::process

#include "lib/metrics.h"

#include <algorithm>
#include <cmath>

#include "vknerf/error.h"

namespace vknerf::nerf {

double mse(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size() || a.empty()) throw Error("mse: images differ in size or are empty");
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += double(a[i] - b[i]) * double(a[i] - b[i]);
  return s / double(a.size());
}

double psnrFromMse(double m) { return m <= 1e-10 ? 100.0 : -10.0 * std::log10(m); }

double psnr(const std::vector<float>& a, const std::vector<float>& b) { return psnrFromMse(mse(a, b)); }

double ssim(const std::vector<float>& a, const std::vector<float>& b, uint32_t w, uint32_t h) {
  if (a.size() != b.size() || a.size() != size_t(w) * h * 3) throw Error("ssim: images differ in size");
  constexpr int R = 5;  // 11x11 window
  double g[2 * R + 1], gs = 0;
  for (int i = -R; i <= R; ++i) gs += g[i + R] = std::exp(-double(i * i) / (2 * 1.5 * 1.5));
  for (double& v : g) v /= gs;
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  // Images smaller than the window use a clamped window (so tiny test images still get a value).
  int x0 = std::min<int>(R, (w - 1) / 2), y0 = std::min<int>(R, (h - 1) / 2);
  double total = 0;
  size_t count = 0;
  for (int c = 0; c < 3; ++c)
    for (int y = y0; y < int(h) - y0; ++y)
      for (int x = x0; x < int(w) - x0; ++x) {
        double ma = 0, mb = 0, aa = 0, bb = 0, ab = 0, ws = 0;
        for (int dy = -R; dy <= R; ++dy)
          for (int dx = -R; dx <= R; ++dx) {
            int yy = y + dy, xx = x + dx;
            if (yy < 0 || xx < 0 || yy >= int(h) || xx >= int(w)) continue;
            double wt = g[dy + R] * g[dx + R];
            double va = a[(size_t(yy) * w + xx) * 3 + c], vb = b[(size_t(yy) * w + xx) * 3 + c];
            ws += wt, ma += wt * va, mb += wt * vb, aa += wt * va * va, bb += wt * vb * vb, ab += wt * va * vb;
          }
        ma /= ws, mb /= ws, aa = aa / ws - ma * ma, bb = bb / ws - mb * mb, ab = ab / ws - ma * mb;
        total += ((2 * ma * mb + c1) * (2 * ab + c2)) / ((ma * ma + mb * mb + c1) * (aa + bb + c2));
        ++count;
      }
  return total / double(count);
}

}  // namespace vknerf::nerf

#include "support/similarity_alignment.h"

#include <algorithm>
#include <cmath>

namespace vknerf::test {

std::array<double, 3> Similarity::apply(const std::array<double, 3>& p) const {
  std::array<double, 3> q;
  for (int r = 0; r < 3; ++r) q[r] = s * (R[3 * r] * p[0] + R[3 * r + 1] * p[1] + R[3 * r + 2] * p[2]) + t[r];
  return q;
}

namespace {

// The eigenvector of the largest eigenvalue of a symmetric 4x4 matrix (cyclic Jacobi).
std::array<double, 4> dominantEigenvector(std::array<double, 16> a) {
  std::array<double, 16> v{};
  for (int i = 0; i < 4; ++i) v[5 * i] = 1;
  for (int sweep = 0; sweep < 50; ++sweep)
    for (int p = 0; p < 4; ++p)
      for (int q = p + 1; q < 4; ++q) {
        if (std::fabs(a[4 * p + q]) < 1e-300) continue;
        const double theta = 0.5 * std::atan2(2 * a[4 * p + q], a[4 * q + q] - a[4 * p + p]);
        const double c = std::cos(theta), s = std::sin(theta);
        for (int k = 0; k < 4; ++k) {  // a = J^T a J, v = v J
          const double akp = a[4 * k + p], akq = a[4 * k + q];
          a[4 * k + p] = c * akp - s * akq, a[4 * k + q] = s * akp + c * akq;
        }
        for (int k = 0; k < 4; ++k) {
          const double apk = a[4 * p + k], aqk = a[4 * q + k];
          a[4 * p + k] = c * apk - s * aqk, a[4 * q + k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 4; ++k) {
          const double vkp = v[4 * k + p], vkq = v[4 * k + q];
          v[4 * k + p] = c * vkp - s * vkq, v[4 * k + q] = s * vkp + c * vkq;
        }
      }
  int best = 0;
  for (int i = 1; i < 4; ++i)
    if (a[5 * i] > a[5 * best]) best = i;
  return {v[best], v[4 + best], v[8 + best], v[12 + best]};
}

}  // namespace

Similarity alignSimilarity(const std::vector<std::array<double, 3>>& from, const std::vector<std::array<double, 3>>& to) {
  const size_t n = from.size();
  std::array<double, 3> mf{}, mt{};
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) mf[k] += from[i][k] / double(n), mt[k] += to[i][k] / double(n);
  double S[3][3] = {}, varFrom = 0;
  for (size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      varFrom += (from[i][a] - mf[a]) * (from[i][a] - mf[a]);
      for (int b = 0; b < 3; ++b) S[a][b] += (from[i][a] - mf[a]) * (to[i][b] - mt[b]);
    }
  // Horn: the rotation's quaternion is the dominant eigenvector of this symmetric matrix.
  const double xx = S[0][0], xy = S[0][1], xz = S[0][2], yx = S[1][0], yy = S[1][1], yz = S[1][2], zx = S[2][0],
               zy = S[2][1], zz = S[2][2];
  const std::array<double, 16> N = {xx + yy + zz, yz - zy,      zx - xz,       xy - yx,       yz - zy, xx - yy - zz,
                                    xy + yx,      zx + xz,      zx - xz,       xy + yx,       -xx + yy - zz, yz + zy,
                                    xy - yx,      zx + xz,      yz + zy,       -xx - yy + zz};
  const auto q = dominantEigenvector(N);
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Similarity out;
  out.R = {w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y),
           2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x),
           2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z};
  double trace = 0;  // sum over points of (to - mt) . R (from - mf)
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) trace += out.R[3 * r + c] * S[c][r];
  out.s = trace / varFrom;
  const auto rf = Similarity{out.s, out.R, {0, 0, 0}}.apply(mf);
  for (int k = 0; k < 3; ++k) out.t[k] = mt[k] - rf[k];
  return out;
}

double rotationAngleDegrees(const std::array<double, 9>& a, const std::array<double, 9>& b) {
  double trace = 0;  // trace(a^T b)
  for (int i = 0; i < 9; ++i) trace += a[i] * b[i];
  return std::acos(std::clamp((trace - 1) / 2, -1.0, 1.0)) * 180 / M_PI;
}

}  // namespace vknerf::test

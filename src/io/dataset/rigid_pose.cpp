// The check every loader makes of a pose it reads: a rigid camera-to-world matrix.
#include <algorithm>
#include <cmath>

#include "io/dataset/dataset_loaders.h"
#include "vknerf/error.h"

namespace vknerf::io::detail {

void checkRigid(const std::array<double, 16>& m, const std::string& where, const char* field) {
  for (double v : m)
    if (!std::isfinite(v)) throw Error(where + ": " + field + " has a non-finite entry");
  // 1e-3 accepts matrices printed with 4+ significant digits and catches any scale, shear or mirror
  // a pose could carry by mistake.
  constexpr double kTol = 1e-3;
  double worst = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += m[4 * k + a] * m[4 * k + b];
      worst = std::max(worst, std::fabs(dot - (a == b ? 1.0 : 0.0)));
    }
  if (worst > kTol)
    throw Error(where + ": " + field + " rotation part is not orthonormal (|R^T R - I| = " +
                std::to_string(worst) + "); poses must be rigid");
  double det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
               m[2] * (m[4] * m[9] - m[5] * m[8]);
  if (std::fabs(det - 1) > kTol)
    throw Error(where + ": " + field + " rotation part has determinant " + std::to_string(det) +
                " (a reflection); poses must be rigid");
  if (std::fabs(m[12]) > kTol || std::fabs(m[13]) > kTol || std::fabs(m[14]) > kTol || std::fabs(m[15] - 1) > kTol)
    throw Error(where + ": " + field + " last row is not (0, 0, 0, 1)");
}

}  // namespace vknerf::io::detail

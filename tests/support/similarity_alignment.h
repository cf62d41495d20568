#pragma once
// The similarity (scale s, rotation R, translation t) that best maps one set of points onto
// another in the least-squares sense (Umeyama 1991, via Horn's quaternion form), to compare poses
// recovered up to a similarity (COLMAP's) with the true ones.
#include <array>
#include <vector>

namespace vknerf::test {

struct Similarity {
  double s = 1;
  std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major
  std::array<double, 3> t{0, 0, 0};
  std::array<double, 3> apply(const std::array<double, 3>& p) const;
};

// Minimises sum |s R from_i + t - to_i|^2; needs 3 or more points not on one line.
Similarity alignSimilarity(const std::vector<std::array<double, 3>>& from, const std::vector<std::array<double, 3>>& to);

// The angle in degrees of the rotation taking a to b (both row-major rotation matrices).
double rotationAngleDegrees(const std::array<double, 9>& a, const std::array<double, 9>& b);

}  // namespace vknerf::test

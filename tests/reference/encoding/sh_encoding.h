#pragma once
// CPU reference for shaders/encoding/encode_sh.comp: real spherical harmonics of a unit direction (x, y, z)
// up to degree 4 in the basis and sign convention of instant-ngp / tiny-cuda-nn's SH encoding
// (Condon-Shortley phase), orthonormal on the unit sphere: integral of Y_i Y_j dOmega = delta_ij.
// Coefficient order: band n = 0..degree-1, m = -n..n, n^2 + n + m in all. The constants are
//   C0 = 1/2 sqrt(1/pi)          = 0.28209479177387814
//   C1 = sqrt(3/(4 pi))          = 0.48860251190291987
//   C2 = 1/2 sqrt(15/pi)         = 1.0925484305920792,  1/4 sqrt(5/pi) = 0.31539156525251999 (x3: 0.94617469575755997),
//        1/4 sqrt(15/pi)         = 0.54627421529603959
//   C3 = 1/4 sqrt(35/(2 pi))     = 0.59004358992664352, 1/2 sqrt(105/pi) = 2.8906114426405538,
//        1/4 sqrt(21/(2 pi))     = 0.45704579946446572, 1/4 sqrt(7/pi)   = 0.3731763325901154,
//        1/4 sqrt(105/pi)        = 1.4453057213202769
// The direction is used as given (rays.comp writes unit vectors); off the sphere the values are
// the same polynomials, finite for any finite input.
#include <cstdint>
#include <vector>

namespace vknerf::ref {

// degree: 1..4 bands, degree^2 coefficients (instant-ngp's "degree 4" is 16 outputs).
template <class T> std::vector<T> shEncoding(const T* d, uint32_t degree) {
  const T x = d[0], y = d[1], z = d[2];
  const T xy = x * y, xz = x * z, yz = y * z, x2 = x * x, y2 = y * y, z2 = z * z;
  std::vector<T> o(16);
  o[0] = T(0.28209479177387814);
  o[1] = T(-0.48860251190291987) * y;
  o[2] = T(0.48860251190291987) * z;
  o[3] = T(-0.48860251190291987) * x;
  o[4] = T(1.0925484305920792) * xy;
  o[5] = T(-1.0925484305920792) * yz;
  o[6] = T(0.94617469575755997) * z2 - T(0.31539156525251999);
  o[7] = T(-1.0925484305920792) * xz;
  o[8] = T(0.54627421529603959) * x2 - T(0.54627421529603959) * y2;
  o[9] = T(0.59004358992664352) * y * (T(-3) * x2 + y2);
  o[10] = T(2.8906114426405538) * xy * z;
  o[11] = T(0.45704579946446572) * y * (T(1) - T(5) * z2);
  o[12] = T(0.3731763325901154) * z * (T(5) * z2 - T(3));
  o[13] = T(0.45704579946446572) * x * (T(1) - T(5) * z2);
  o[14] = T(1.4453057213202769) * z * (x2 - y2);
  o[15] = T(0.59004358992664352) * x * (-x2 + T(3) * y2);
  o.resize(size_t(degree) * degree);
  return o;
}

}  // namespace vknerf::ref

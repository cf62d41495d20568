#pragma once
// CPU reference for the learned far field (src/models/common/far_field.h): the colour a ray sees at
// infinity in its direction d is  bg(d) = MLP(hash(d / |d|)),  a hash grid read on the unit sphere
// (inside the grid's [-1, 1]^3) and a dense MLP ending in a sigmoid. A ray's composited colour is
// C = sum w_i c_i + T_final bg(d), so dL/dbg = dL/dC * T_final, and T_final = 1 - opacity. Its shape
// (FarFieldShape) is production's: src/core/layouts/far_field_shape.h.
#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

#include "core/layouts/far_field_shape.h"
#include "reference/encoding/hash_encoding.h"
#include "reference/network/mlp.h"

namespace vknerf::ref {

using core::FarFieldShape;

template <class T> std::array<T, 3> unitDirection(const T* d) {
  const T n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return {d[0] / n, d[1] / n, d[2] / n};
}

// The table in the precision T the encoding runs in: the caller's own vector when it already is
// (a finite-difference check calls this hundreds of times over the whole table), else a copy.
template <class T, class P> decltype(auto) tableAs(const std::vector<P>& table) {
  if constexpr (std::is_same_v<T, P>) return (table);
  else return std::vector<T>(table.begin(), table.end());
}

// bg(d): rgb in (0, 1).
template <class T, class P>
std::array<T, 3> farFieldColor(const FarFieldShape& s, const std::vector<P>& table, const std::vector<P>& mlp,
                               const T* direction) {
  const auto u = unitDirection(direction);
  const auto features = hashEncoding(s.grid, tableAs<T>(table).data(), u.data());
  const auto acts = denseMlpForward<T>(s.mlp, mlp, features.data());
  return {acts.back()[0], acts.back()[1], acts.back()[2]};
}

// tableGrads and mlpGrads += d(dColor . C) / d params for one ray whose composite has `opacity`:
// the background's share of the ray's colour gradient, back through the MLP and the grid.
template <class T, class P>
void farFieldBackward(const FarFieldShape& s, const std::vector<P>& table, const std::vector<P>& mlp, const T* direction,
                      T opacity, const T* dColor, std::vector<T>& tableGrads, std::vector<T>& mlpGrads) {
  const auto u = unitDirection(direction);
  const auto features = hashEncoding(s.grid, tableAs<T>(table).data(), u.data());
  const auto acts = denseMlpForward<T>(s.mlp, mlp, features.data());
  const T transmittance = T(1) - opacity;
  const T dBg[3] = {dColor[0] * transmittance, dColor[1] * transmittance, dColor[2] * transmittance};
  std::vector<T> dFeatures(features.size(), T(0));
  denseMlpBackward(s.mlp, mlp, features.data(), acts, dBg, mlpGrads, dFeatures.data());
  hashEncodingBackward(s.grid, u.data(), dFeatures.data(), tableGrads.data());
}

}  // namespace vknerf::ref

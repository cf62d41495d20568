#pragma once
// CPU reference for the proposal estimator's two kernels (nerfacto's proposal sampling, mip-NeRF
// 360's interlevel loss), in float or double:
//   shaders/sampling/proposal_sample.comp     a ray's candidates and a cheap density at each ->
//                                             n samples placed by inverse CDF of its weights
//   shaders/sampling/proposal_interlevel.comp the field's weights on those samples -> the loss that
//                                             makes the proposal's weights bound them, and its
//                                             gradient for the proposal's densities
//
// A ray's candidates are the occupancy march's samples (t_i, delta_i): sorted, not overlapping, with
// gaps where the march skipped empty cells. Both kernels measure along the ray in occupied length,
// u(t) = the candidates' length in front of t, so a gap costs nothing: candidate i is the interval
// [u_i, u_i + delta_i] with u_0 = 0, and U = sum delta_i the ray's whole occupied length. A new
// sample is a bin [e_j, e_j+1] in u, evaluated at its midpoint and composited with delta = its
// length in u, so the n samples tile exactly the length the candidates tiled.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "reference/occupancy/occupancy_grid.h"
#include "reference/render/composite.h"
#include "reference/sampling/samplers.h"

namespace vknerf::ref {

// Candidate i's optical depth; a density reads as the occupancy grid reads it (NaN as 0, inf as
// the largest float).
template <class T> T candidateDepth(std::span<const T> candidates, std::span<const T> sigma, size_t i) {
  return opticalDepth(sanitizeDensity(sigma[i]), candidates[2 * i + 1]);
}

// The candidates' starts in occupied length, u[0] = 0 .. u[k] = U, each adding max(delta, 0).
template <class T> std::vector<T> occupiedStarts(std::span<const T> candidates) {
  std::vector<T> u(candidates.size() / 2 + 1, T(0));
  for (size_t i = 0; i + 1 < u.size(); ++i) u[i + 1] = u[i] + std::max(candidates[2 * i + 1], T(0));
  return u;
}

// w_i = T_i alpha_i of the candidates (t, delta pairs) under densities sigma (one per candidate).
template <class T> std::vector<T> proposalWeights(std::span<const T> candidates, std::span<const T> sigma) {
  std::vector<T> w(sigma.size());
  T prefix = 0;
  for (size_t i = 0; i < sigma.size(); ++i) {
    T x = candidateDepth(candidates, sigma, i);
    w[i] = std::exp(-prefix) * alphaOf(x);
    prefix += x;
  }
  return w;
}

// Candidate i's share of the sampling mass: its weight (clamped at 0, NaN to 0) plus a uniform
// share `padding` of the whole spread over the occupied length, so that no stretch the proposal
// calls empty goes without samples for ever (nerfacto's histogram padding, by length here).
// Annealed (a in [0, 1), the first steps of training), the weight is w^a (l / U)^(1 - a) of its
// length l in the occupied length U: from uniform by length at a = 0 to the weights at a = 1
// (nerfacto's w^a over its bins of equal length, here with candidates of any length).
template <class T> T proposalMass(T weight, T delta, T padding, T occupiedLength, T anneal = T(1)) {
  const T share = delta / occupiedLength;
  T w = weight > T(0) ? weight : T(0);
  if (anneal < T(1) && w > T(0)) w = std::pow(w, anneal) * std::pow(share, T(1) - anneal);
  return w + padding * share;
}

// The samples a ray of k candidates gets (proposal_count.comp): n, but at most the march steps the
// candidates stand for (each up to `span`), and none without candidates.
inline uint32_t proposalCount(uint64_t k, uint32_t n, uint32_t span) {
  return uint32_t(std::min<uint64_t>(n, k * span));
}

// Edge quantile j of n bins (j = 1 .. n-1): (j + shift) / n, shift in [-1/2, 1/2) from one draw a
// ray in training (0 when rendering), so the edges stay in order and every bin keeps 1/n of the mass.
template <class T> T edgeQuantile(uint32_t j, uint32_t n, T shift) { return (T(j) + shift) / T(n); }
template <class T> T proposalShift(uint32_t seed, uint32_t ray, bool jitter) {
  return jitter ? T(rng01(seed, ray, 0)) - T(0.5) : T(0);
}

// The n samples (t, delta pairs) the proposal's densities place on a ray's candidates. A ray
// without occupied length gets n samples (0, 0), which weigh nothing. When the masses sum to
// nothing usable (below kMinMass, inf or NaN) every candidate's mass is its length (uniform).
template <class T>
std::vector<T> proposalSamples(std::span<const T> candidates, std::span<const T> sigma, uint32_t n, T padding,
                               T shift, T anneal = T(1)) {
  const size_t k = sigma.size();
  std::vector<T> out(2 * n, T(0));
  const std::vector<T> u = occupiedStarts(candidates);
  auto len = [&](size_t i) { return std::max(candidates[2 * i + 1], T(0)); };
  const T length = u[k];
  if (n == 0 || !(length > T(0))) return out;

  std::vector<T> w = proposalWeights(candidates, sigma), mass(k);
  T total = 0;
  for (size_t i = 0; i < k; ++i) total += mass[i] = proposalMass(w[i], len(i), padding, length, anneal);
  if (!(total >= T(kMinMass) && total <= T(3.402823466e38))) {
    total = 0;
    for (size_t i = 0; i < k; ++i) total += mass[i] = len(i);
  }

  // The edges in u: 0, the inverse CDF at the quantiles, U.
  std::vector<T> edges(n + 1);
  edges[0] = 0;
  edges[n] = length;
  size_t i = 0;
  T below = 0;  // the mass in front of candidate i
  for (uint32_t j = 1; j < n; ++j) {
    T target = edgeQuantile(j, n, shift) * total;
    while (i + 1 < k && below + mass[i] < target) below += mass[i++];
    T frac = (target - below) / std::max(mass[i], T(kMinMass));
    T e = u[i] + std::clamp(frac, T(0), T(1)) * len(i);
    edges[j] = std::clamp(e, edges[j - 1], length);
  }

  // Each bin's midpoint back to t; its length in u is its delta.
  size_t c = 0;
  for (uint32_t j = 0; j < n; ++j) {
    T mid = (edges[j] + edges[j + 1]) / 2;
    while (c + 1 < k && u[c + 1] <= mid) ++c;
    out[2 * j] = candidates[2 * c] + std::clamp(mid - u[c], T(0), len(c));
    out[2 * j + 1] = edges[j + 1] - edges[j];
  }
  return out;
}

// The interlevel loss (mip-NeRF 360, eq. 13) of one ray: the field's weights w_j on its samples
// (bins [e_j, e_j+1] in u, e the prefix sums of the samples' deltas) against the proposal's weights
// on the candidates. A sample's bound B_j is the proposal weight of every candidate that overlaps
// its bin by a positive length; L = weight * sum_j max(0, w_j - B_j)^2 / (w_j + eps), a field
// weight clamped into [0, 1] (NaN to 0). Only the proposal learns from it (the field's weights are
// constants here, as nerfacto stops their gradient).
inline constexpr float kInterlevelEpsilon = 1e-7f;  // nerfacto's: float's machine epsilon

template <class T> struct InterlevelResult {
  T loss = 0;
  std::vector<T> dWeights;  // dL/d(proposal weight) per candidate
  std::vector<T> dSigma;    // dL/d(proposal density) per candidate
};

// Candidate i and sample j overlap when their intervals in u share a positive length.
template <class T> bool overlapsPositively(T a0, T a1, T b0, T b1) { return std::min(a1, b1) > std::max(a0, b0); }

template <class T>
InterlevelResult<T> interlevelLoss(std::span<const T> candidates, std::span<const T> sigma,
                                   std::span<const T> samples, std::span<const T> fieldWeights, T weight = 1,
                                   T epsilon = T(kInterlevelEpsilon)) {
  const size_t k = sigma.size(), n = fieldWeights.size();
  const std::vector<T> u = occupiedStarts(candidates), e = occupiedStarts(samples);
  std::vector<T> w = proposalWeights(candidates, sigma);

  InterlevelResult<T> r;
  r.dWeights.assign(k, T(0));
  for (size_t j = 0; j < n; ++j) {
    T bound = 0;
    for (size_t i = 0; i < k; ++i)
      if (overlapsPositively(u[i], u[i + 1], e[j], e[j + 1])) bound += w[i];
    T fw = fieldWeights[j] >= T(0) ? std::min(fieldWeights[j], T(1)) : T(0);
    T excess = std::max(fw - bound, T(0));
    r.loss += weight * excess * excess / (fw + epsilon);
    T dBound = -2 * weight * excess / (fw + epsilon);
    for (size_t i = 0; i < k; ++i)
      if (overlapsPositively(u[i], u[i + 1], e[j], e[j + 1])) r.dWeights[i] += dBound;
  }
  // A loss g(w) of the weights reaches sigma_k as delta_k T_k+1 (g_k - Q_k), Q_k the weights'
  // gradients behind k seen from k: Q_k-1 = g_k alpha_k + (1 - alpha_k) Q_k (reference/render/composite.h).
  r.dSigma.assign(k, T(0));
  std::vector<T> tOut(k);
  T prefix = 0;
  for (size_t i = 0; i < k; ++i) tOut[i] = std::exp(-(prefix += candidateDepth(candidates, sigma, i)));
  T q = 0;
  for (size_t i = k; i-- > 0;) {
    T delta = candidates[2 * i + 1];
    T alpha = alphaOf(candidateDepth(candidates, sigma, i));
    r.dSigma[i] = delta > T(0) ? delta * tOut[i] * (r.dWeights[i] - q) : T(0);
    q = r.dWeights[i] * alpha + (T(1) - alpha) * q;
  }
  return r;
}

}  // namespace vknerf::ref

#pragma once
// CPU reference for shaders/sample_stratified.comp and shaders/sample_pdf.comp, in float or double.
// In float it evaluates the same formulas in the same order as the shaders (which mark them
// `precise`, so no FMA contraction), so it reproduces their output to within rounding of division;
// in double it is the oracle the float path is measured against.
//
// A sample is (t, delta): sorted by t within a ray, delta_i = t_{i+1} - t_i, and the last segment
// closes at the ray's far bound. A ray that misses (t_near < 0) or is empty (t_far <= t_near) gets
// all samples (max(t_near, 0), 0).
#include <algorithm>
#include <cstdint>
#include <vector>

#include "reference/rng.h"

namespace vknerf::ref {

template <class T> struct Sample {
  T t = 0, delta = 0;
};

// Masses below this count as none (uniform fallback) and it bounds every denominator: far above
// float's denormal range, so a device that flushes denormals behaves like one that keeps them.
inline constexpr float kMinMass = 1e-30f;

template <class T> bool emptyRay(T tNear, T tFar) { return tNear < T(0) || !(tFar > tNear); }

template <class T> std::vector<Sample<T>> emptySamples(T tNear, uint32_t n) {
  return std::vector<Sample<T>>(n, Sample<T>{std::max(tNear, T(0)), T(0)});
}

// Sorted t's to samples: each delta reaches the next t, the last one reaches tFar.
template <class T> std::vector<Sample<T>> closeSegments(const std::vector<T>& ts, T tFar) {
  std::vector<Sample<T>> out(ts.size());
  for (size_t i = 0; i < ts.size(); ++i) {
    T next = i + 1 < ts.size() ? ts[i + 1] : tFar;
    out[i] = {ts[i], std::max(next - ts[i], T(0))};
  }
  return out;
}

// ---- Stratified ----

// Sample i of n in [tNear, tFar] at fraction u of its bin. The min() keeps rounding of
// tNear + 1 * (tFar - tNear) from stepping past tFar (u near 1 can round i + u up to i + 1).
template <class T> T stratifiedT(T tNear, T tFar, uint32_t i, uint32_t n, T u) {
  return std::min(tNear + (T(i) + u) / T(n) * (tFar - tNear), tFar);
}

template <class T> T stratifiedJitter(uint32_t seed, uint32_t ray, uint32_t i, bool jitter) {
  return jitter ? T(rng01(seed, ray, i)) : T(0.5);
}

template <class T>
std::vector<Sample<T>> stratifiedSamples(T tNear, T tFar, uint32_t n, uint32_t seed, uint32_t ray, bool jitter) {
  if (emptyRay(tNear, tFar)) return emptySamples(tNear, n);
  std::vector<T> ts(n);
  for (uint32_t i = 0; i < n; ++i) ts[i] = stratifiedT(tNear, tFar, i, n, stratifiedJitter<T>(seed, ray, i, jitter));
  return closeSegments(ts, tFar);
}

// ---- Inverse CDF ----

// A piecewise-constant density: bin k = [edges[k], edges[k+1]] holds mass[k] >= 0 (not normalised);
// cum[k] = mass[0] + ... + mass[k], accumulated left to right as the shader does.
template <class T> struct Cdf {
  std::vector<T> edges, mass, cum;
  T total() const { return cum.empty() ? T(0) : cum.back(); }
};

template <class T> Cdf<T> makeCdf(std::vector<T> edges, const std::vector<T>& weights, T padding) {
  Cdf<T> c{std::move(edges), {}, {}};
  T sum = 0;
  for (T w : weights) {
    c.mass.push_back((w > T(0) ? w : T(0)) + padding);  // (w > 0) also maps a NaN weight to 0
    sum += c.mass.back();
    c.cum.push_back(sum);
  }
  return c;
}

// The weights carry no usable distribution: (almost) no mass, a non-finite sum, or no length.
template <class T> bool needsUniformFallback(const Cdf<T>& c) {
  T total = c.total();
  bool massOk = total >= T(kMinMass) && total <= T(3.402823466e38f);
  return !massOk || !(c.edges.back() > c.edges.front());
}

// Inverse of the CDF at u in [0, 1]: the first bin k whose cumulative mass reaches u * total, then
// linear interpolation inside it, clamped to the bin so that rounding never unsorts samples.
template <class T> T invertCdf(const Cdf<T>& c, T u) {
  size_t last = c.mass.size() - 1, k = 0;
  T v = u * c.total();
  while (k < last && c.cum[k] < v) ++k;
  T below = k ? c.cum[k - 1] : T(0);
  T lo = c.edges[k], hi = c.edges[k + 1];
  T t = lo + (v - below) / std::max(c.mass[k], T(kMinMass)) * std::max(hi - lo, T(0));
  return std::min(std::max(t, lo), hi);
}

// Draw j of n: stratified in [0, 1] (so the draws come out sorted), jittered or at bin centres.
template <class T> T fineDraw(uint32_t seed, uint32_t ray, uint32_t j, uint32_t n, bool jitter) {
  return (T(j) + (jitter ? T(rng01(seed, ray, j)) : T(0.5))) / T(n);
}

// The nFine fine t's of one ray: bins are the coarse segments [t_k, t_{k+1}] (the last one closing
// at tFar), or the single bin [tNear, tFar] when the weights carry no distribution.
template <class T>
std::vector<T> fineSamples(T tNear, T tFar, const std::vector<T>& coarseT, const std::vector<T>& weights,
                           uint32_t nFine, uint32_t seed, uint32_t ray, bool jitter, T padding) {
  std::vector<T> edges = coarseT;
  edges.push_back(tFar);
  Cdf<T> cdf = makeCdf(std::move(edges), weights, padding);
  if (needsUniformFallback(cdf)) cdf = Cdf<T>{{tNear, tFar}, {T(1)}, {T(1)}};
  std::vector<T> out(nFine);
  for (uint32_t j = 0; j < nFine; ++j) out[j] = invertCdf(cdf, fineDraw<T>(seed, ray, j, nFine, jitter));
  return out;
}

// The coarse and fine t's of one ray merged in order, with deltas recomputed.
template <class T>
std::vector<Sample<T>> importanceSamples(T tNear, T tFar, const std::vector<T>& coarseT, const std::vector<T>& weights,
                                         uint32_t nFine, uint32_t seed, uint32_t ray, bool jitter, T padding) {
  uint32_t n = uint32_t(coarseT.size()) + nFine;
  if (emptyRay(tNear, tFar)) return emptySamples(tNear, n);
  std::vector<T> fine = fineSamples(tNear, tFar, coarseT, weights, nFine, seed, ray, jitter, padding);
  std::vector<T> all(n);
  std::merge(coarseT.begin(), coarseT.end(), fine.begin(), fine.end(), all.begin());
  return closeSegments(all, tFar);
}

}  // namespace vknerf::ref

#pragma once
// CPU reference for shaders/sampling/sample_stratified.comp and shaders/sampling/sample_pdf.comp, in float or double.
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

template <class T> Cdf<T> cdfOfMasses(std::vector<T> edges, std::vector<T> mass) {
  Cdf<T> c{std::move(edges), std::move(mass), {}};
  T sum = 0;
  for (T m : c.mass) c.cum.push_back(sum += m);
  return c;
}

// Mass of a coarse weight: clamped at 0 ((w > 0) also maps a NaN weight to 0), then padded.
template <class T> T paddedMass(T w, T padding) { return (w > T(0) ? w : T(0)) + padding; }

template <class T> Cdf<T> makeCdf(std::vector<T> edges, const std::vector<T>& weights, T padding) {
  std::vector<T> mass;
  for (T w : weights) mass.push_back(paddedMass(w, padding));
  return cdfOfMasses(std::move(edges), std::move(mass));
}

// Inverse of the CDF at u in [0, 1]: the first bin with mass whose cumulative mass reaches u * total
// (the chapter's F_{k-1} < u <= F_k; at u = 0 the first bin with mass), then linear interpolation
// inside it, clamped to the bin so that rounding never unsorts samples.
template <class T> T invertCdf(const Cdf<T>& c, T u) {
  size_t last = c.mass.size() - 1, k = 0;
  T v = u * c.total();
  while (k < last && (c.mass[k] <= T(0) || c.cum[k] < v)) ++k;
  T below = k ? c.cum[k - 1] : T(0);
  T lo = c.edges[k], hi = c.edges[k + 1];
  T t = lo + (v - below) / std::max(c.mass[k], T(kMinMass)) * std::max(hi - lo, T(0));
  return std::min(std::max(t, lo), hi);
}

// The fine pass's density along one ray. Bins: [t_near, t_0] (no mass), then the coarse segments
// [t_k, t_{k+1}], the last one closing at t_far, with the padded coarse weights. When those carry
// no usable distribution (almost no mass, a non-finite sum, or coarse segments of no length) every
// bin's mass becomes its width: uniform over [t_near, t_far].
template <class T>
Cdf<T> rayCdf(T tNear, T tFar, const std::vector<T>& coarseT, const std::vector<T>& weights, T padding) {
  std::vector<T> edges{tNear};
  edges.insert(edges.end(), coarseT.begin(), coarseT.end());
  edges.push_back(tFar);
  std::vector<T> mass{T(0)};
  for (T w : weights) mass.push_back(paddedMass(w, padding));
  Cdf<T> c = cdfOfMasses(edges, mass);
  T total = c.total();
  bool massOk = total >= T(kMinMass) && total <= T(3.402823466e38f);
  if (massOk && edges.back() > edges[1]) return c;
  for (size_t k = 0; k < mass.size(); ++k) mass[k] = std::max(edges[k + 1] - edges[k], T(0));
  return cdfOfMasses(std::move(edges), std::move(mass));
}

// Draw j of n: stratified in [0, 1] (so the draws come out sorted), jittered or at bin centres.
template <class T> T fineDraw(uint32_t seed, uint32_t ray, uint32_t j, uint32_t n, bool jitter) {
  return (T(j) + (jitter ? T(rng01(seed, ray, j)) : T(0.5))) / T(n);
}

// The nFine fine t's of one ray, sorted.
template <class T>
std::vector<T> fineSamples(T tNear, T tFar, const std::vector<T>& coarseT, const std::vector<T>& weights,
                           uint32_t nFine, uint32_t seed, uint32_t ray, bool jitter, T padding) {
  Cdf<T> cdf = rayCdf(tNear, tFar, coarseT, weights, padding);
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

#pragma once
// CPU reference for shaders/occupancy.glsl and the occupancy_*, march_* and scan_* kernels, in
// float or double. In float it evaluates the same formulas in the same order as the shaders (which
// mark them `precise`), so the march reproduces the shaders' sample sets exactly; the march here
// is the plain one-lattice-point-at-a-time loop that the shaders' empty-space skipping must equal.
#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <vector>

#include "reference/rng.h"

namespace vknerf::ref {

inline constexpr uint32_t kMaxMarchSteps = 16777216u;  // lattice points per ray, exact in float

// ---- Grid layout: cell (x, y, z) of an R^3 grid is x + R (y + R z); bit (i & 31) of word i >> 5 ----

inline uint32_t cellIndex(uint32_t x, uint32_t y, uint32_t z, uint32_t r) { return x + r * (y + r * z); }
inline uint32_t wordsFor(uint32_t numCells) { return (numCells + 31u) / 32u; }
inline bool bitSet(const std::vector<uint32_t>& bits, uint32_t i) { return (bits[i >> 5] >> (i & 31u)) & 1u; }
inline void setBit(std::vector<uint32_t>& bits, uint32_t i) { bits[i >> 5] |= 1u << (i & 31u); }

inline uint32_t countOccupied(const std::vector<uint32_t>& bits, uint32_t numCells) {
  uint32_t n = 0;
  for (uint32_t i = 0; i < numCells; ++i) n += bitSet(bits, i);
  return n;
}

// ---- Update ----

struct CellPoint {
  uint32_t cell;
  std::array<float, 3> position;  // in the normalised box [-1, 1]^3
};

// Point j of an update: cell j, or a random cell; jittered inside it by rng01(seed, j, axis).
template <class T> std::array<T, 3> cellPointPosition(uint32_t cell, uint32_t r, uint32_t seed, uint32_t j) {
  uint32_t c[3] = {cell % r, (cell / r) % r, cell / (r * r)};
  std::array<T, 3> p;
  for (int k = 0; k < 3; ++k) p[k] = (T(c[k]) + T(rng01(seed, j, uint32_t(k)))) * (T(2) / T(r)) - T(1);
  return p;
}

inline uint32_t cellPointCell(uint32_t r, uint32_t seed, uint32_t j, bool randomCells) {
  return randomCells ? rngUint(seed, j, 3u) % (r * r * r) : j;
}

template <class T> T sanitizeDensity(T sigma) { return sigma >= T(0) ? std::min(sigma, T(FLT_MAX)) : T(0); }

template <class T> T emaDensity(T old, T decay, T fresh) { return std::max(old * decay, fresh); }

// One update: fresh[cell] = max of the sanitised densities measured in it (0 if none), then
// d = max(d decay, fresh) for every cell and bits = d > threshold.
template <class T>
void updateGrid(std::vector<T>& density, std::vector<uint32_t>& bits, const std::vector<uint32_t>& cells,
                const std::vector<T>& measured, T decay, T threshold) {
  std::vector<T> fresh(density.size(), T(0));
  for (size_t j = 0; j < cells.size(); ++j) fresh[cells[j]] = std::max(fresh[cells[j]], sanitizeDensity(measured[j]));
  bits.assign(wordsFor(uint32_t(density.size())), 0u);
  for (size_t i = 0; i < density.size(); ++i) {
    density[i] = emaDensity(density[i], decay, fresh[i]);
    if (density[i] > threshold) setBit(bits, uint32_t(i));
  }
}

// ---- March ----

template <class T> struct MarchSample {
  T t = 0, delta = 0;
};

struct MarchParams {
  std::array<float, 3> boxMin{-1, -1, -1};
  std::array<float, 3> gridScale{64, 64, 64};  // R / (boxMax - boxMin), as the host computes it
  uint32_t resolution = 128;
  float dt = 0;
  uint32_t maxSamples = 0;
  uint32_t seed = 0;
  bool jitter = false;
};

// The host's grid scale (nerf::RayMarcher computes the same expression in float).
inline std::array<float, 3> gridScale(uint32_t r, const std::array<float, 3>& boxMin, const std::array<float, 3>& boxMax) {
  return {float(r) / (boxMax[0] - boxMin[0]), float(r) / (boxMax[1] - boxMin[1]), float(r) / (boxMax[2] - boxMin[2])};
}

// Samples of one ray: every lattice point t_k = t_near + (u + k) dt with t_k < t_far whose cell is
// occupied, in order, at most maxSamples, each (t_k, min(dt, t_far - t_k)). None when the ray
// misses (t_near < 0).
template <class T>
std::vector<MarchSample<T>> marchRay(const std::array<T, 3>& o, const std::array<T, 3>& d, T tNear, T tFar,
                                     uint32_t ray, const MarchParams& p, const std::vector<uint32_t>& bits) {
  std::vector<MarchSample<T>> out;
  if (!(tNear >= T(0)) || p.maxSamples == 0) return out;
  std::array<T, 3> go, gd;
  for (int k = 0; k < 3; ++k) {
    go[k] = (o[k] - T(p.boxMin[k])) * T(p.gridScale[k]);
    gd[k] = d[k] * T(p.gridScale[k]);
  }
  T u = p.jitter ? T(rng01(p.seed, ray, 0u)) : T(0), dt = T(p.dt);
  T top = T(p.resolution - 1);
  for (uint32_t k = 0; k < kMaxMarchSteps; ++k) {
    T t = tNear + (u + T(k)) * dt;
    if (!(t < tFar)) break;
    uint32_t c[3];
    for (int a = 0; a < 3; ++a) c[a] = uint32_t(std::clamp(std::floor(go[a] + t * gd[a]), T(0), top));
    if (!bitSet(bits, cellIndex(c[0], c[1], c[2], p.resolution))) continue;
    out.push_back({t, std::min(dt, tFar - t)});
    if (out.size() == p.maxSamples) break;
  }
  return out;
}

// ---- Early termination ----

// Samples a ray keeps when compositing stops once transmittance falls below a threshold: sample i
// is kept while the optical depth in front of it, sum_{j<i} sigma_j delta_j, is at most
// maxOpticalDepth = -ln(threshold) (so T_i >= threshold; the sample that crosses the threshold is
// kept, the ones behind it are not). The dropped samples carry at most T_cut < threshold of light.
template <class T>
uint32_t keptSamples(const std::vector<T>& sigma, const std::vector<T>& delta, T maxOpticalDepth) {
  T depth = 0;
  uint32_t i = 0;
  for (; i < sigma.size() && depth <= maxOpticalDepth; ++i) depth += sanitizeDensity(sigma[i]) * delta[i];
  return i;
}

}  // namespace vknerf::ref

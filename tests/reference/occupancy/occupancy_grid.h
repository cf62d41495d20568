#pragma once
// CPU reference for shaders/occupancy/occupancy.glsl and the occupancy_*, march_* and scan_* kernels, in
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
// With C nested cascades, cell = cascade * R^3 + local cell, and cascade c spans
// [-2^(c - C + 1), 2^(c - C + 1)]^3 of the normalised box (the outermost one is the whole box).
template <class T>
std::array<T, 3> cellPointPosition(uint32_t cell, uint32_t r, uint32_t seed, uint32_t j, uint32_t cascades = 1) {
  const uint32_t cells = r * r * r, cascade = cell / cells, local = cell % cells;
  uint32_t c[3] = {local % r, (local / r) % r, local / (r * r)};
  const T scale = T(std::ldexp(1.0f, int(cascade) - int(cascades - 1)));
  std::array<T, 3> p;
  for (int k = 0; k < 3; ++k) p[k] = ((T(c[k]) + T(rng01(seed, j, uint32_t(k)))) * (T(2) / T(r)) - T(1)) * scale;
  return p;
}

inline uint32_t cellPointCell(uint32_t r, uint32_t seed, uint32_t j, bool randomCells, uint32_t cascades = 1) {
  return randomCells ? rngUint(seed, j, 3u) % (r * r * r * cascades) : j;
}

template <class T> T sanitizeDensity(T sigma) { return sigma >= T(0) ? std::min(sigma, T(FLT_MAX)) : T(0); }

// A negative density marks a cell no training camera sees (ref::markUnseenEmpty): it stays empty.
template <class T> T emaDensity(T old, T decay, T fresh) { return old < T(0) ? old : std::max(old * decay, fresh); }

// One update: fresh[cell] = max of the sanitised densities measured in it (0 if none), then
// d = max(d decay, fresh) for every cell (a negative d stays) and bits = d > threshold.
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

// ---- Cascaded march with cone stepping (unbounded scenes) ----
//
// C nested cubes around the box centre, cascade c twice the side of cascade c - 1, each an R^3 grid;
// cascade 0 is the inner cube, cascade C - 1 the whole box. Grid coordinates g are cascade 0's
// (gridScale and boxMin describe the inner cube): a point belongs to the smallest cascade holding
// it, m = max_a |g_a - R/2| / (R/2) <= 2^c (the outermost for anything beyond), and its cell there is
// floor((g - R/2) 2^-c + R/2), clamped. Cell index: c R^3 + x + R (y + R z).
//
// Steps follow instant-ngp's cone: dt(t) = clamp(t * coneAngle, dtMin, dtMax), a step that grows
// with distance once past t = dtMin / coneAngle. The march starts at t_near + u dt(t_near) (u: the
// jitter) and from a sample at t goes to t + dt(t). In an empty cell it jumps by whole steps of the
// current dt to the first point past the cell's exit: n = max(1, ceil((t_exit - t) / dt(t))).

//
// Opacity-bounded steps (stepOpacity > 0): the sample at t stands for n steps [t, t + n dt(t)), n
// the largest up to `stretch` for which every point t + k dt (0 < k < n) lies before t_far in an
// occupied cell and n dt times the largest running-maximum density (negatives as 0) of the cells of
// t, ..., t + (n - 1) dt is at most stepOpacity; the march goes on from t + n dt. A stepOpacity of
// FLT_MAX stretches through every occupied cell without reading a density.

struct ConeMarchParams {
  MarchParams base;       // boxMin, gridScale: the inner cube's; dt: dtMin
  uint32_t cascades = 1;
  float coneAngle = 0, dtMax = 0;
  float stepOpacity = 0;  // 0: no stretching
  uint32_t stretch = 1;
};

template <class T> T coneStep(T t, const ConeMarchParams& p) {
  return std::clamp(t * T(p.coneAngle), T(p.base.dt), T(p.dtMax));
}

// Cascade of a point in cascade 0's grid coordinates.
template <class T> uint32_t cascadeOf(const std::array<T, 3>& g, uint32_t r, uint32_t cascades) {
  const T half = T(r) * T(0.5);
  T m = T(0);
  for (int a = 0; a < 3; ++a) m = std::max(m, std::abs(g[a] - half) / half);
  uint32_t c = 0;
  while (c + 1 < cascades && m > T(std::ldexp(1.0f, int(c)))) ++c;
  return c;
}

// Cell of a point in cascade c, clamped into its grid.
template <class T> std::array<uint32_t, 3> cascadeCell(const std::array<T, 3>& g, uint32_t r, uint32_t c) {
  const T half = T(r) * T(0.5), s = T(std::ldexp(1.0f, -int(c))), top = T(r - 1);
  std::array<uint32_t, 3> cell;
  for (int a = 0; a < 3; ++a) cell[a] = uint32_t(std::clamp(std::floor((g[a] - half) * s + half), T(0), top));
  return cell;
}

// Samples of one ray, (t, min(dt(t), t_far - t)), in order, at most maxSamples; none for a miss.
// `density`: the grid's running maxima, read only for stretched steps.
template <class T>
std::vector<MarchSample<T>> marchRayCascaded(const std::array<T, 3>& o, const std::array<T, 3>& d, T tNear, T tFar,
                                             uint32_t ray, const ConeMarchParams& p, const std::vector<uint32_t>& bits,
                                             const std::vector<float>& density = {}) {
  std::vector<MarchSample<T>> out;
  const MarchParams& b = p.base;
  if (!(tNear >= T(0)) || b.maxSamples == 0) return out;
  std::array<T, 3> go, gd;
  for (int k = 0; k < 3; ++k) {
    go[k] = (o[k] - T(b.boxMin[k])) * T(b.gridScale[k]);
    gd[k] = d[k] * T(b.gridScale[k]);
  }
  const uint32_t r = b.resolution, cells = r * r * r;
  const T half = T(r) * T(0.5);
  T t = tNear;
  if (b.jitter) t = t + T(rng01(b.seed, ray, 0u)) * coneStep(t, p);
  for (uint32_t i = 0; i < kMaxMarchSteps && t < tFar; ++i) {
    const T dt = coneStep(t, p);
    std::array<T, 3> g;
    for (int a = 0; a < 3; ++a) g[a] = go[a] + t * gd[a];
    const uint32_t c = cascadeOf(g, r, p.cascades);
    const auto cell = cascadeCell(g, r, c);
    T next;
    const uint32_t index = c * cells + cellIndex(cell[0], cell[1], cell[2], r);
    if (bitSet(bits, index)) {
      uint32_t n = 1;
      if (p.stepOpacity > 0.0f) {
        const bool bounded = p.stepOpacity < FLT_MAX;  // else every occupied cell, no density read
        T sigma = bounded ? std::max(T(density[index]), T(0)) : T(0);
        for (; n < p.stretch; ++n) {
          const T tk = t + T(n) * dt;
          if (!(tk < tFar)) break;
          std::array<T, 3> gk;
          for (int a = 0; a < 3; ++a) gk[a] = go[a] + tk * gd[a];
          const uint32_t ck = cascadeOf(gk, r, p.cascades);
          const auto cellK = cascadeCell(gk, r, ck);
          const uint32_t ik = ck * cells + cellIndex(cellK[0], cellK[1], cellK[2], r);
          if (!bitSet(bits, ik)) break;
          if (!bounded) continue;
          const T s = std::max(sigma, T(density[ik]));
          if (!(s * (T(n + 1) * dt) <= T(p.stepOpacity))) break;
          sigma = s;
        }
      }
      const T step = T(n) * dt;
      out.push_back({t, std::min(step, tFar - t)});
      if (out.size() == b.maxSamples) break;
      next = t + step;
    } else {
      const T scale = T(std::ldexp(1.0f, int(c)));
      T tExit = T(FLT_MAX);
      for (int a = 0; a < 3; ++a) {
        if (gd[a] == T(0)) continue;
        const T bound = gd[a] > T(0) ? T(cell[a] + 1u) : T(cell[a]);
        tExit = std::min(tExit, ((bound - half) * scale + half - go[a]) / gd[a]);
      }
      const T steps = std::max(T(1), std::ceil((tExit - t) / dt));
      next = t + steps * dt;
    }
    if (!(next > t)) break;  // t so large that a step no longer moves it
    t = next;
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

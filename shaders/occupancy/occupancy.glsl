// Occupancy grid and lattice march shared by the occupancy_* and march_* kernels;
// tests/reference/occupancy/occupancy_grid.h is the CPU twin of every formula here. Formulas are `precise` so that
// no driver contracts them into FMAs and the float reference reproduces them bit for bit.
//
// Grid: R^3 cells over the scene box; cell (x, y, z) has linear index x + R (y + R z) and is
// occupied when bit (index & 31) of word index >> 5 is set. Grid coordinates g = (x - boxMin) *
// R / (boxMax - boxMin) run over [0, R]^3; a ray o + t d becomes go + t gd in them.
#ifndef VKNERF_OCCUPANCY_GLSL
#define VKNERF_OCCUPANCY_GLSL

#include "common/float_limits.glsl"
#include "common/rng.glsl"
#include "common/flat_index.glsl"

// Lattice points per ray are counted in a uint and converted to float: stay where that is exact.
const uint kMaxMarchSteps = 16777216u;

uint cellIndex(uvec3 c, uint r) { return c.x + r * (c.y + r * c.z); }

bool bitSet(uint word, uint index) { return ((word >> (index & 31u)) & 1u) != 0u; }

// A field value as the grid stores it: NaN and negatives count as empty space, +inf as the largest
// float, so that neither poisons the running maximum for good.
float sanitizeDensity(float sigma) { return sigma >= 0.0 ? min(sigma, kMaxFloat) : 0.0; }

// instant-ngp's update: decay the running value, but never below what was just measured. A
// negative value marks a cell no training camera sees (occupancy_mark_unseen.comp): it stays.
float emaDensity(float old, float decay, float fresh) {
  precise float decayed = old * decay;
  return old < 0.0 ? old : max(decayed, fresh);
}

// Four cells' share of the grid's mean density (occupancy_mean.comp, and occupancy_ema.comp's word
// sums): a non-finite density, and the -1 of a cell no camera sees, count as 0.
float occupancyMeanTerm(vec4 d) {
  bvec4 finite = not(bvec4(uvec4(isnan(d)) | uvec4(isinf(d))));
  vec4 c = mix(vec4(0.0), max(d, vec4(0.0)), finite);
  return (c.x + c.y) + (c.z + c.w);
}

// Lattice point k of a ray: t_k = t_near + (u + k) dt, computed from k (never accumulated) so that
// a skip of n points lands exactly where n single steps would.
float latticeT(float tNear, float u, float dt, uint k) {
  precise float t = tNear + (u + float(k)) * dt;
  return t;
}

vec3 gridPoint(vec3 go, vec3 gd, float t) {
  precise vec3 p = go + t * gd;
  return p;
}

// Cell of a grid point, clamped into the grid: points a rounding error outside the box belong to
// the border cell. Clamping in float first keeps huge or negative values out of the int cast.
uvec3 cellOf(vec3 p, uint r) { return uvec3(clamp(floor(p), vec3(0.0), vec3(float(r - 1u)))); }

// ---- March with empty-space skipping (the includer defines OCCUPANCY_MARCH and declares
// `vec4 rays[]`, `uint occupancyBits[]` and `float gridDensity[]` before including) ----
#ifdef OCCUPANCY_MARCH

layout(local_size_x = 32) in;  // one invocation per ray; small groups spread few rays over threads

#include "sampling/march_shared.h"

struct MarchRay {
  vec3 go, gd;       // origin and direction in grid coordinates
  float tNear, tFar;
  float u;           // jitter of the first lattice point, in steps
  float dt;
  uint r;            // grid resolution
};

// Number of lattice points with t_k < t_far (0 for a ray that misses). Estimated by division, then
// settled exactly by the same comparison the one-step march makes: t_k is monotone in k.
uint marchEnd(MarchRay m) {
  if (!(m.tNear >= 0.0)) return 0u;
  float estimate = clamp(ceil((m.tFar - m.tNear) / m.dt - m.u), 0.0, float(kMaxMarchSteps));
  uint k = uint(estimate);
  while (k > 0u && !(latticeT(m.tNear, m.u, m.dt, k - 1u) < m.tFar)) --k;
  while (k < kMaxMarchSteps && latticeT(m.tNear, m.u, m.dt, k) < m.tFar) ++k;
  return k;
}

// The cell of lattice point k, and how many consecutive points from k lie in it (>= 1): the run
// ends at the first point past the cell's exit. The run is verified, not trusted: grid coordinates
// and cells are monotone in k under float rounding, so when point k + n - 1 is still in the cell
// so are all points before it, and no point is ever attributed to the wrong cell by a rounded exit
// distance. A failed check falls back to a run of one.
uint cellRun(MarchRay m, uint k, out bool occupied) {
  float t = latticeT(m.tNear, m.u, m.dt, k);
  uvec3 c = cellOf(gridPoint(m.go, m.gd, t), m.r);
  uint index = cellIndex(c, m.r);
  occupied = bitSet(occupancyBits[index >> 5u], index);
  float tExit = kMaxFloat;
  for (int a = 0; a < 3; ++a) {
    if (m.gd[a] != 0.0) {
      float bound = m.gd[a] > 0.0 ? float(c[a] + 1u) : float(c[a]);
      tExit = min(tExit, (bound - m.go[a]) / m.gd[a]);
    }
  }
  float steps = min(ceil((tExit - t) / m.dt), float(kMaxMarchSteps));
  if (!(steps > 1.0)) return 1u;
  uint n = uint(steps);
  uvec3 last = cellOf(gridPoint(m.go, m.gd, latticeT(m.tNear, m.u, m.dt, k + n - 1u)), m.r);
  return all(equal(last, c)) ? n : 1u;
}

uint marchRayIndex() { return flatIndex(32u); }

MarchRay marchRay(uint ray) {
  vec4 a = rays[2u * ray], b = rays[2u * ray + 1u];
  MarchRay m;
  precise vec3 go = (a.xyz - pc.boxMin.xyz) * pc.gridScale.xyz;
  precise vec3 gd = b.xyz * pc.gridScale.xyz;
  m.go = go;
  m.gd = gd;
  m.tNear = a.w;
  m.tFar = b.w;
  m.u = pc.jitter != 0u ? rng01(pc.seed, ray, 0u) : 0.0;
  m.dt = pc.boxMin.w;
  m.r = pc.resolution;
  return m;
}

// Samples of a ray from a march: (t, delta) with delta = dt, shortened so it never crosses t_far.
vec2 marchSample(MarchRay m, uint k) {
  float t = latticeT(m.tNear, m.u, m.dt, k);
  precise float rest = m.tFar - t;
  return vec2(t, min(m.dt, rest));
}

// ---- Cascaded march with cone stepping (ref::marchRayCascaded): boxMin and gridScale describe
// the inner cube, cascade c is 2^c times its side around the same centre, each an R^3 grid ----

float coneStep(float t) { return clamp(t * pc.coneAngle, pc.boxMin.w, pc.dtMax); }

// 2^c exactly (exp2 need not be).
float powerOfTwo(uint c) { return float(1u << c); }

// Smallest cascade holding grid point g (cascade 0's coordinates), the outermost for anything beyond.
uint cascadeOf(vec3 g, uint r) {
  float half_ = float(r) * 0.5;
  vec3 q = abs(g - half_) / half_;
  float m = max(max(max(0.0, q.x), q.y), q.z);
  uint c = 0u;
  while (c + 1u < pc.cascades && m > powerOfTwo(c)) ++c;
  return c;
}

// The cell of g in cascade c, clamped into that cascade's grid.
uvec3 cascadeCell(MarchRay m, vec3 g, uint c) {
  float half_ = float(m.r) * 0.5, s = 1.0 / powerOfTwo(c);
  precise vec3 local = (g - half_) * s + half_;
  return cellOf(local, m.r);
}

uint cascadeCellIndex(uvec3 cell, uint c, uint r) { return c * r * r * r + cellIndex(cell, r); }

// Whether the cell of g in cascade c is occupied, its index, and the t at which the ray leaves it.
bool cascadeCellOccupied(MarchRay m, vec3 g, uint c, float t, out float tExit, out uint index) {
  float half_ = float(m.r) * 0.5, scale = powerOfTwo(c);
  uvec3 cell = cascadeCell(m, g, c);
  index = cascadeCellIndex(cell, c, m.r);
  tExit = kMaxFloat;
  for (int a = 0; a < 3; ++a) {
    if (m.gd[a] != 0.0) {
      float bound = m.gd[a] > 0.0 ? float(cell[a] + 1u) : float(cell[a]);
      precise float exitA = ((bound - half_) * scale + half_ - m.go[a]) / m.gd[a];
      tExit = min(tExit, exitA);
    }
  }
  return bitSet(occupancyBits[index >> 5u], index);
}

// First t of the march: t_near, plus u steps when jittered.
float coneStart(MarchRay m) {
  precise float t = m.tNear + m.u * coneStep(m.tNear);
  return t;
}

// Opacity-bounded steps (pc.stepOpacity > 0): the sample at t stands for n cone steps [t, t + n dt)
// instead of one, n the largest up to pc.stretch for which every point t + k dt (0 < k < n) lies
// before t_far in an occupied cell, and n dt times the largest running-maximum density of the cells
// of t, ..., t + (n - 1) dt is at most pc.stepOpacity. Through a faint fog (a half-transparent
// cloth, haze) one sample then does the work of n, each no more opaque than the bound; a dense cell
// keeps the plain step, and an empty one ends the stretch, so no sample spans empty space. A bound
// of the largest float stretches through every occupied cell (the proposal's candidates) and reads
// no density: on lavapipe each read is a scalar gather per lane.
float stretchedStep(MarchRay m, float t, float dt, uint index) {
  if (!(pc.stepOpacity > 0.0)) return dt;
  bool bounded = pc.stepOpacity < kMaxFloat;
  float sigma = bounded ? max(gridDensity[index], 0.0) : 0.0;
  uint n = 1u;
  for (; n < pc.stretch; ++n) {
    precise float tk = t + float(n) * dt;
    if (!(tk < m.tFar)) break;
    vec3 g = gridPoint(m.go, m.gd, tk);
    uint c = cascadeOf(g, m.r);
    uint i = cascadeCellIndex(cascadeCell(m, g, c), c, m.r);
    if (!bitSet(occupancyBits[i >> 5u], i)) break;
    if (!bounded) continue;
    float s = max(sigma, gridDensity[i]);
    precise float depth = s * (float(n + 1u) * dt);
    if (!(depth <= pc.stepOpacity)) break;
    sigma = s;
  }
  precise float stretched = float(n) * dt;
  return stretched;
}

// One visit of the cone march at t (< t_far): true when t lies in an occupied cell, a sample
// (t, dt) with dt the cone step, stretched through a fog by stretchedStep, and t moves past it;
// false in an empty cell, and t jumps over the cell in whole steps of the current dt. t becomes
// +inf once a step no longer moves it. A ray's march is one loop of visits while t < t_far: a
// sample or an empty cell an iteration. (A loop per sample with an inner loop over the empty cells
// before it ran slower on 8-wide SIMD: at every sample the lanes waited for the one with the most
// empty cells before its next sample.)
bool coneVisit(MarchRay m, inout float t, out vec2 sample_) {
  float dt = coneStep(t);
  vec3 g = gridPoint(m.go, m.gd, t);
  float tExit;
  uint index;
  bool occupied = cascadeCellOccupied(m, g, cascadeOf(g, m.r), t, tExit, index);
  precise float next;
  if (occupied) {
    dt = stretchedStep(m, t, dt, index);
    sample_ = vec2(t, dt);
    next = t + dt;
  } else {
    sample_ = vec2(0.0);
    precise float steps = max(1.0, ceil((tExit - t) / dt));
    next = t + steps * dt;
  }
  t = next > t ? next : kMaxFloat;
  return occupied;
}

// ---- A ray's samples stored in order (the includer defines OCCUPANCY_MARCH_STORE and
// `void storeSample(uint s, vec2 sample_, uint ray)` before including) ----
#ifdef OCCUPANCY_MARCH_STORE

// Marches ray `ray` and stores its samples (t, delta) at s, s + 1, ... before `end`, delta
// shortened so that no sample crosses t_far; returns the index past the last one stored.
uint marchRayInto(MarchRay m, uint ray, uint s, uint end) {
  if (pc.cascades > 1u) {
    if (!(m.tNear >= 0.0)) return s;
    float t = coneStart(m);
    vec2 sample_;
    for (uint i = 0u; i < kMaxMarchSteps && s < end && t < m.tFar; ++i) {
      if (!coneVisit(m, t, sample_)) continue;
      storeSample(s, vec2(sample_.x, min(sample_.y, m.tFar - sample_.x)), ray);
      ++s;
    }
    return s;
  }
  uint kEnd = marchEnd(m);
  for (uint k = 0u; k < kEnd && s < end;) {
    bool occupied;
    uint run = cellRun(m, k, occupied);
    if (occupied)
      for (uint j = k, stop = min(k + run, kEnd); j < stop && s < end; ++j, ++s) storeSample(s, marchSample(m, j), ray);
    k += run;
  }
  return s;
}

#endif  // OCCUPANCY_MARCH_STORE

#endif  // OCCUPANCY_MARCH

#endif

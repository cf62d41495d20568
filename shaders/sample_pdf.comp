#version 450
// Hierarchical (fine) sampling: inverse-CDF draws from the coarse pass's weights, merged in order
// with the coarse samples. One invocation per ray, streaming: the draws come out sorted, so the bin
// search is a pointer that only moves forward, and the merge emits each sample as soon as its
// successor is known. No per-ray arrays, hence no bound on the sample counts.
#extension GL_GOOGLE_include_directive : require
#include "sampling.glsl"

layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };        // (o, t_near), (d, t_far)
layout(std430, binding = 1) readonly buffer Coarse { vec2 coarse[]; };    // (t, delta), nCoarse per ray
layout(std430, binding = 2) readonly buffer Weights { float weights[]; }; // nCoarse per ray
layout(std430, binding = 3) writeonly buffer Merged { vec2 merged[]; };   // nCoarse + nFine per ray

layout(push_constant) uniform Push {
  uint numRays;
  uint nCoarse;
  uint nFine;
  uint seed;
  uint jitter;
  float padding;
} pc;

uint coarseBase;
float tFar;

// Bin k's mass; (w > 0) also maps a NaN weight to 0.
float massOf(uint k) {
  float w = weights[coarseBase + k];
  precise float m = (w > 0.0 ? w : 0.0) + pc.padding;
  return m;
}
// Bin edges are the coarse t's, closed by the ray's far bound.
float edgeOf(uint k) { return k < pc.nCoarse ? coarse[coarseBase + k].x : tFar; }

// The forward-only walk over the bins: bin k = [lo, hi] with mass m, cumulative mass `below`
// before it and `through` up to its end.
struct Walk {
  uint k, last;
  float lo, hi, m, below, through, total;
};

float nextFine(inout Walk w, uint ray, uint j) {
  precise float v = fineDraw(pc.seed, ray, j, pc.nFine, pc.jitter != 0u) * w.total;
  while (w.k < w.last && w.through < v) {
    w.k++;
    w.below = w.through;
    w.lo = w.hi;
    w.hi = edgeOf(w.k + 1u);
    w.m = massOf(w.k);
    precise float through = w.below + w.m;
    w.through = through;
  }
  precise float t = w.lo + (v - w.below) / max(w.m, kMinMass) * max(w.hi - w.lo, 0.0);
  return min(max(t, w.lo), w.hi);
}

void main() {
  uint ray = flatInvocation();
  if (ray >= pc.numRays) return;
  uint nc = pc.nCoarse, nf = pc.nFine, nOut = nc + nf;
  uint outBase = ray * nOut;  // the host keeps numRays * nOut below 2^32
  coarseBase = ray * nc;
  float tNear = rays[2u * ray].w;
  tFar = rays[2u * ray + 1u].w;
  if (emptyRay(tNear, tFar)) {
    for (uint o = 0u; o < nOut; ++o) merged[outBase + o] = vec2(max(tNear, 0.0), 0.0);
    return;
  }

  precise float total = 0.0;
  for (uint k = 0u; k < nc; ++k) total += massOf(k);
  bool massOk = total >= kMinMass && total <= kMaxFloat;  // false for NaN too
  Walk w;
  if (massOk && edgeOf(nc) > edgeOf(0u)) {
    w = Walk(0u, nc - 1u, edgeOf(0u), edgeOf(1u), massOf(0u), 0.0, 0.0, total);
  } else {  // no usable distribution: one bin [t_near, t_far] holding everything
    w = Walk(0u, 0u, tNear, tFar, 1.0, 0.0, 0.0, 1.0);
  }
  w.through = w.m;

  uint i = 0u, j = 0u;
  float tCoarse = nc > 0u ? coarse[coarseBase].x : 0.0;
  float tFine = nf > 0u ? nextFine(w, ray, 0u) : 0.0;
  float prev = 0.0;
  for (uint o = 0u; o < nOut; ++o) {
    float cur;
    if (i < nc && (j >= nf || tCoarse <= tFine)) {
      cur = tCoarse;
      ++i;
      if (i < nc) tCoarse = coarse[coarseBase + i].x;
    } else {
      cur = tFine;
      ++j;
      if (j < nf) tFine = nextFine(w, ray, j);
    }
    if (o > 0u) merged[outBase + o - 1u] = vec2(prev, max(cur - prev, 0.0));
    prev = cur;
  }
  if (nOut > 0u) merged[outBase + nOut - 1u] = vec2(prev, max(tFar - prev, 0.0));
}

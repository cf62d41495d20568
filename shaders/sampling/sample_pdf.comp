#version 450
// Hierarchical (fine) sampling: inverse-CDF draws from the coarse pass's weights, merged in order
// with the coarse samples (tests/reference/sampling/samplers.h: rayCdf, invertCdf, importanceSamples).
// One invocation per ray walks the bins [t_near, t_0], [t_0, t_1], ..., [t_last, t_far] once,
// front to back. The draws come out sorted, so every step emits exactly one output sample: either
// the next fine draw, inside the current bin, or a step into the next bin, whose start is the next
// coarse sample. nCoarse + nFine steps for every ray, whatever its weights: on lavapipe's 8-lane
// SIMD no lane waits on another's inner loop. No per-ray arrays, hence no bound on the counts.
#extension GL_GOOGLE_include_directive : require
#include "sampling/sampling.glsl"

layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };        // (o, t_near), (d, t_far)
layout(std430, binding = 1) readonly buffer Coarse { vec2 coarse[]; };    // (t, delta), nCoarse per ray
layout(std430, binding = 2) readonly buffer Weights { float weights[]; }; // nCoarse per ray
layout(std430, binding = 3) writeonly buffer Merged { vec2 merged[]; };   // nCoarse + nFine per ray

#include "sampling/sample_pdf_shared.h"

uint coarseBase;
float tNear, tFar;
bool uniformBins;  // the weights carry no distribution: each bin's mass is its width

// Edge b of the bins: t_near, the coarse t's, t_far.
float edgeOf(uint b) { return b == 0u ? tNear : b <= pc.nCoarse ? coarse[coarseBase + b - 1u].x : tFar; }

// Coarse weight k clamped at 0 ((w > 0) also maps a NaN weight to 0), then padded.
float paddedMass(uint k) {
  float w = weights[coarseBase + k];
  precise float m = (w > 0.0 ? w : 0.0) + pc.padding;
  return m;
}

// Mass of bin b = [lo, hi]; bin 0, before the first coarse sample, has none unless uniform.
float binMass(uint b, float lo, float hi) {
  if (uniformBins) return max(hi - lo, 0.0);
  return b == 0u ? 0.0 : paddedMass(b - 1u);
}

void main() {
  uint ray = flatInvocation();
  if (ray >= pc.numRays) return;
  uint nc = pc.nCoarse, nf = pc.nFine, nOut = nc + nf;
  uint outBase = ray * nOut;  // the host keeps numRays * nOut below 2^32
  coarseBase = ray * nc;
  tNear = rays[2u * ray].w;
  tFar = rays[2u * ray + 1u].w;
  if (emptyRay(tNear, tFar)) {
    for (uint o = 0u; o < nOut; ++o) merged[outBase + o] = vec2(max(tNear, 0.0), 0.0);
    return;
  }

  precise float total = 0.0;
  for (uint k = 0u; k < nc; ++k) total += paddedMass(k);
  bool massOk = total >= kMinMass && total <= kMaxFloat;  // false for NaN too
  uniformBins = !(massOk && tFar > edgeOf(1u));
  if (uniformBins) {
    total = 0.0;
    float lo = tNear;
    for (uint b = 1u; b <= nc + 1u; ++b) {
      float hi = edgeOf(b);
      total += max(hi - lo, 0.0);
      lo = hi;
    }
  }

  // Bin b = [lo, hi] with mass m; `below` and `through` are the cumulative masses at its ends.
  uint b = 0u, j = 0u;
  float lo = tNear, hi = edgeOf(1u), m = binMass(0u, lo, hi), below = 0.0;
  precise float through = below + m;
  precise float v = fineDraw(pc.seed, ray, 0u, nf, pc.jitter != 0u) * total;  // the next draw's target mass
  float prev = 0.0;
  for (uint o = 0u; o < nOut; ++o) {
    float cur;
    if (b < nc && (j >= nf || m <= 0.0 || through < v)) {  // into the next bin: emit its coarse sample
      ++b;
      below = through;
      lo = hi;
      hi = edgeOf(b + 1u);
      m = binMass(b, lo, hi);
      through = below + m;
      cur = lo;
    } else {  // the next fine draw lies in this bin
      precise float t = lo + (v - below) / max(m, kMinMass) * max(hi - lo, 0.0);
      cur = min(max(t, lo), hi);
      ++j;
      v = fineDraw(pc.seed, ray, j, nf, pc.jitter != 0u) * total;
    }
    if (o > 0u) merged[outBase + o - 1u] = vec2(prev, max(cur - prev, 0.0));
    prev = cur;
  }
  if (nOut > 0u) merged[outBase + nOut - 1u] = vec2(prev, max(tFar - prev, 0.0));
}

#version 450
// Stratified samples along each ray: N equal bins in [t_near, t_far], one sample per bin, jittered
// or at the bin centre. One invocation per ray, each sample's t carried over as its predecessor's
// `next`: on lavapipe this is about 3x faster than one invocation per sample, which pays an integer
// division, two ray loads and a second hash per sample.
#extension GL_GOOGLE_include_directive : require
#include "sampling/sampling.glsl"

layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };        // (o, t_near), (d, t_far)
layout(std430, binding = 1) writeonly buffer Samples { vec2 samples[]; };  // (t, delta), N per ray

#include "sampling/sample_stratified_shared.h"

float jitterOf(uint ray, uint i) { return pc.jitter != 0u ? rng01(pc.seed, ray, i) : 0.5; }

void main() {
  uint ray = flatInvocation();
  if (ray >= pc.numRays) return;
  uint n = pc.samplesPerRay, base = ray * n;
  float tNear = rays[2u * ray].w, tFar = rays[2u * ray + 1u].w;
  if (emptyRay(tNear, tFar)) {
    for (uint i = 0u; i < n; ++i) samples[base + i] = vec2(max(tNear, 0.0), 0.0);
    return;
  }
  float t = stratifiedT(tNear, tFar, 0u, n, jitterOf(ray, 0u));
  for (uint i = 0u; i < n; ++i) {
    float next = i + 1u < n ? stratifiedT(tNear, tFar, i + 1u, n, jitterOf(ray, i + 1u)) : tFar;
    samples[base + i] = vec2(t, max(next - t, 0.0));
    t = next;
  }
}

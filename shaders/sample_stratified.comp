#version 450
// Stratified samples along each ray: N equal bins in [t_near, t_far], one sample per bin, jittered
// or at the bin centre. One invocation per sample: each recomputes its successor's t (two hashes)
// rather than looping over the ray, which on lavapipe would carry live state across iterations.
#extension GL_GOOGLE_include_directive : require
#include "sampling.glsl"

layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };        // (o, t_near), (d, t_far)
layout(std430, binding = 1) writeonly buffer Samples { vec2 samples[]; };  // (t, delta), N per ray

layout(push_constant) uniform Push {
  uint numRays;
  uint samplesPerRay;
  uint seed;
  uint jitter;
} pc;

float jitterOf(uint ray, uint i) { return pc.jitter != 0u ? rng01(pc.seed, ray, i) : 0.5; }

void main() {
  uint s = flatInvocation();
  uint n = pc.samplesPerRay;
  if (s >= pc.numRays * n) return;  // the host keeps numRays * n below 2^32
  uint ray = s / n, i = s - ray * n;
  float tNear = rays[2u * ray].w, tFar = rays[2u * ray + 1u].w;
  if (emptyRay(tNear, tFar)) {
    samples[s] = vec2(max(tNear, 0.0), 0.0);
    return;
  }
  float t = stratifiedT(tNear, tFar, i, n, jitterOf(ray, i));
  float next = i + 1u < n ? stratifiedT(tNear, tFar, i + 1u, n, jitterOf(ray, i + 1u)) : tFar;
  samples[s] = vec2(t, max(next - t, 0.0));
}

// Shared by the sampling kernels; tests/reference/sampling/samplers.h is the CPU twin of every formula here.
// Formulas are `precise` so that no driver contracts them into FMAs and the float reference
// reproduces them.
#ifndef VKNERF_SAMPLING_GLSL
#define VKNERF_SAMPLING_GLSL

#include "common/float_limits.glsl"
#include "common/rng.glsl"
#include "common/flat_index.glsl"

// Masses below this count as none and it bounds every denominator (ref::kMinMass).
const float kMinMass = 1e-30;

// Misses the box, or has no length: every sample becomes (max(t_near, 0), 0).
bool emptyRay(float tNear, float tFar) { return tNear < 0.0 || !(tFar > tNear); }

// Sample i of n in [tNear, tFar] at fraction u of its bin; min() stops rounding past tFar.
float stratifiedT(float tNear, float tFar, uint i, uint n, float u) {
  precise float t = tNear + (float(i) + u) / float(n) * (tFar - tNear);
  return min(t, tFar);
}

// Fine draw j of n in [0, 1]: stratified, so draws come out sorted.
float fineDraw(uint seed, uint ray, uint j, uint n, bool jitter) {
  precise float u = (float(j) + (jitter ? rng01(seed, ray, j) : 0.5)) / float(n);
  return u;
}

// Local size from the host (spec constant 0). Declared here, with a name, because glslang folds a
// gl_WorkGroupSize read that precedes the local_size_x_id declaration to the constant 1.
#include "sampling/sampling_shared.h"

// The flat invocation index at the host's local size.
uint flatInvocation() { return flatIndex(kLocalSize); }

#endif

// Counter-based RNG: a PCG hash of (seed, a, b). Integer-only, so the CPU twin
// (src/core/math/rng.h) reproduces every sample bit for bit.
#ifndef VKNERF_RNG_GLSL
#define VKNERF_RNG_GLSL

uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

uint rngUint(uint seed, uint a, uint b) { return pcgHash(pcgHash(pcgHash(seed) + a) + b); }

// Uniform in [0, 1): the top 24 bits, exactly representable in float.
float rng01(uint seed, uint a, uint b) { return float(rngUint(seed, a, b) >> 8) * (1.0 / 16777216.0); }

#endif

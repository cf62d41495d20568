#pragma once
// CPU twin of shaders/rays/camera_runs.glsl: a training batch of N rays in runs of one camera each,
// run k holding N / C rays (one more for the first N % C runs) and being camera (k + offset) mod C.
#include <algorithm>
#include <cstdint>
#include <utility>

#include "reference/rng.h"

namespace vknerf::ref {

inline uint32_t cameraRunOfRay(uint32_t i, uint32_t N, uint32_t C) {
  const uint32_t base = N / C, extra = N % C, longRays = extra * (base + 1);
  return i < longRays ? i / (base + 1) : extra + (i - longRays) / base;
}

// The rays [first, end) of run k.
inline std::pair<uint32_t, uint32_t> cameraRunRays(uint32_t k, uint32_t N, uint32_t C) {
  const uint32_t base = N / C, extra = N % C, first = k * base + std::min(k, extra);
  return {first, first + base + (k < extra ? 1 : 0)};
}

// The step's rotation of the runs (rays.comp's grouped mode): run 0 is this camera.
inline uint32_t cameraRunOffset(uint32_t seed, uint32_t C) { return rngUint(seed, 0, 2) % C; }

// Ray i's camera in a grouped batch of N rays over C cameras.
inline uint32_t groupedCamera(uint32_t seed, uint32_t i, uint32_t N, uint32_t C) {
  return (cameraRunOfRay(i, N, C) + cameraRunOffset(seed, C)) % C;
}

}  // namespace vknerf::ref

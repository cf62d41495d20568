// The push constants of march_count.comp and march_write.comp (through occupancy/occupancy.glsl); on the host, vknerf::glsl::MarchPush.
#ifndef VKNERF_SAMPLING_MARCH_SHARED_H
#define VKNERF_SAMPLING_MARCH_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(MarchPush)
  vec4 boxMin;      // xyz; w = dt
  vec4 gridScale;   // xyz = R / (boxMax - boxMin), computed once on the host; w unused
  uint numRays;
  uint resolution;  // R
  uint maxSamples;  // cap per ray
  uint seed;
  uint jitter;      // first lattice point at u = rng01(seed, ray, 0) steps, else at t_near
  uint capacity;    // samples the output buffers hold (march_write.comp)
  uint cascades;    // 1: the lattice march over one grid; more: the cascaded cone march below
  float coneAngle;  // cascaded march: dt(t) = clamp(t coneAngle, dt, dtMax)
  float dtMax;
  float stepOpacity;  // cascaded march: > 0 stretches steps through faint cells (stretchedStep), 0 never
  uint stretch;       // the most cone steps one stretched sample stands for
PUSH_CONSTANTS_END

#endif

#version 450
// Pass 1 of the packed march: how many samples each ray gets (occupied lattice points inside
// [t_near, t_far), at most maxSamples). One invocation per ray; march_write.comp repeats the same
// march once the prefix sum has placed each ray's samples.
#extension GL_GOOGLE_include_directive : require
#define OCCUPANCY_MARCH
layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };             // (o, t_near), (d, t_far)
layout(std430, binding = 1) readonly buffer Bits { uint occupancyBits[]; };
layout(std430, binding = 2) writeonly buffer Counts { uint counts[]; };
layout(std430, binding = 3) readonly buffer Density { float gridDensity[]; };  // the grid's running maxima
#include "occupancy/occupancy.glsl"

void main() {
  uint ray = marchRayIndex();
  if (ray >= pc.numRays) return;
  MarchRay m = marchRay(ray);
  if (pc.cascades > 1u) {
    uint n = 0u;
    if (m.tNear >= 0.0) {
      float t = coneStart(m);
      vec2 sample_;
      for (uint i = 0u; i < kMaxMarchSteps && n < pc.maxSamples && t < m.tFar; ++i)
        if (coneVisit(m, t, sample_)) ++n;
    }
    counts[ray] = n;
    return;
  }
  // Whole runs of lattice points per cell: the count costs one iteration per cell crossed.
  uint kEnd = marchEnd(m), n = 0u;
  for (uint k = 0u; k < kEnd && n < pc.maxSamples;) {
    bool occupied;
    uint run = cellRun(m, k, occupied);
    if (occupied) n += min(min(run, kEnd - k), pc.maxSamples - n);
    k += run;
  }
  counts[ray] = n;
}

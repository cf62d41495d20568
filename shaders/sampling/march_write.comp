#version 450
// Pass 2 of the packed march: repeats march_count.comp's march and writes ray r's samples
// (t, delta) and their ray index at [off[r], off[r+1]). The offsets are clamped to the buffers'
// capacity, so a batch over budget loses the samples of its last rays, never memory safety.
#extension GL_GOOGLE_include_directive : require
#define OCCUPANCY_MARCH
layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };             // (o, t_near), (d, t_far)
layout(std430, binding = 1) readonly buffer Bits { uint occupancyBits[]; };
layout(std430, binding = 2) readonly buffer Offsets { uint offsets[]; };       // numRays + 1
layout(std430, binding = 3) writeonly buffer Samples { vec2 samples[]; };      // (t, delta)
layout(std430, binding = 4) writeonly buffer SampleRay { uint sampleRay[]; };
layout(std430, binding = 5) readonly buffer Density { float gridDensity[]; };  // the grid's running maxima
#include "occupancy/occupancy.glsl"

void main() {
  uint ray = marchRayIndex();
  if (ray >= pc.numRays) return;
  uint s = offsets[ray], end = offsets[ray + 1u];
  if (s >= end) return;
  MarchRay m = marchRay(ray);
  if (pc.cascades > 1u) {
    if (!(m.tNear >= 0.0)) return;
    float t = coneStart(m);
    vec2 sample_;
    for (uint i = 0u; i < kMaxMarchSteps && s < end && t < m.tFar; ++i) {
      if (!coneVisit(m, t, sample_)) continue;
      samples[s] = vec2(sample_.x, min(sample_.y, m.tFar - sample_.x));
      sampleRay[s] = ray;
      ++s;
    }
    return;
  }
  uint kEnd = marchEnd(m);
  for (uint k = 0u; k < kEnd && s < end;) {
    bool occupied;
    uint run = cellRun(m, k, occupied);
    if (occupied) {
      for (uint j = k, stop = min(k + run, kEnd); j < stop && s < end; ++j, ++s) {
        samples[s] = marchSample(m, j);
        sampleRay[s] = ray;
      }
    }
    k += run;
  }
}

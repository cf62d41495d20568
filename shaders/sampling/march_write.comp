#version 450
// Pass 2 of the packed march: repeats march_count.comp's march and writes ray r's samples
// (t, delta) and their ray index at [off[r], off[r+1]). The offsets are clamped to the buffers'
// capacity, so a batch over budget loses the samples of its last rays, never memory safety.
#extension GL_GOOGLE_include_directive : require
#define OCCUPANCY_MARCH
#define OCCUPANCY_MARCH_STORE
layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };             // (o, t_near), (d, t_far)
layout(std430, binding = 1) readonly buffer Bits { uint occupancyBits[]; };
layout(std430, binding = 2) readonly buffer Offsets { uint offsets[]; };       // numRays + 1
layout(std430, binding = 3) writeonly buffer Samples { vec2 samples[]; };      // (t, delta)
layout(std430, binding = 4) writeonly buffer SampleRay { uint sampleRay[]; };
layout(std430, binding = 5) readonly buffer Density { float gridDensity[]; };  // the grid's running maxima

void storeSample(uint s, vec2 sample_, uint ray) {
  samples[s] = sample_;
  sampleRay[s] = ray;
}

#include "occupancy/occupancy.glsl"

void main() {
  uint ray = marchRayIndex();
  if (ray >= pc.numRays) return;
  uint s = offsets[ray], end = offsets[ray + 1u];
  if (s >= end) return;
  marchRayInto(marchRay(ray), ray, s, end);
}

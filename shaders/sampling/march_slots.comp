#version 450
// The march in one pass, where every ray has room for all its samples (a render's block: rays x
// the most samples a ray fit the capacity): ray r's samples (t, delta) go to its own slots
// [r maxSamples, (r + 1) maxSamples) and their number to counts[r]. march_compact.comp then packs
// them at the offsets the counts' prefix sum gives, the same batch march_count.comp and
// march_write.comp make with two marches of every ray.
#extension GL_GOOGLE_include_directive : require
#define OCCUPANCY_MARCH
#define OCCUPANCY_MARCH_STORE
layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };             // (o, t_near), (d, t_far)
layout(std430, binding = 1) readonly buffer Bits { uint occupancyBits[]; };
layout(std430, binding = 2) writeonly buffer Counts { uint counts[]; };
layout(std430, binding = 3) writeonly buffer Slots { vec2 slots[]; };          // (t, delta), maxSamples a ray
layout(std430, binding = 4) readonly buffer Density { float gridDensity[]; };  // the grid's running maxima

void storeSample(uint s, vec2 sample_, uint ray) { slots[s] = sample_; }

#include "occupancy/occupancy.glsl"

void main() {
  uint ray = marchRayIndex();
  if (ray >= pc.numRays) return;
  uint first = ray * pc.maxSamples;
  counts[ray] = marchRayInto(marchRay(ray), ray, first, first + pc.maxSamples) - first;
}

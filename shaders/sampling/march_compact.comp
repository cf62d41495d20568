#version 450
// Packs march_slots.comp's samples: ray r's slots [r maxSamples, r maxSamples + counts[r]) go to
// offsets[r], offsets[r] + 1, ... with the ray's index, cut at offsets[r + 1] (offsets clamped to
// the capacity: the samples march_write.comp would drop). One invocation per ray: an invocation
// per slot tested every empty slot too, and a ray's slots are mostly empty (its cap is the most
// samples any ray may take).
#extension GL_GOOGLE_include_directive : require
#include "common/flat_index.glsl"
layout(local_size_x = 32) in;

layout(std430, binding = 0) readonly buffer Counts { uint counts[]; };
layout(std430, binding = 1) readonly buffer Offsets { uint offsets[]; };    // numRays + 1
layout(std430, binding = 2) readonly buffer Slots { vec2 slots[]; };
layout(std430, binding = 3) writeonly buffer Samples { vec2 samples[]; };   // (t, delta)
layout(std430, binding = 4) writeonly buffer SampleRay { uint sampleRay[]; };

#include "sampling/march_compact_shared.h"

void main() {
  uint ray = flatIndex(32u);
  if (ray >= pc.numRays) return;
  uint s = offsets[ray], n = min(counts[ray], offsets[ray + 1u] - s), from = ray * pc.maxSamples;
  for (uint k = 0u; k < n; ++k) {
    samples[s + k] = slots[from + k];
    sampleRay[s + k] = ray;
  }
}

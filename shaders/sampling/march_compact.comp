#version 450
// Packs the samples that early termination kept (march_truncate.comp): ray r's first
// newOff[r+1] - newOff[r] samples move from [off[r], ...) to [newOff[r], ...), with their ray
// index and field values, so backward passes run over the surviving samples only.
#extension GL_GOOGLE_include_directive : require
#include "occupancy/occupancy.glsl"

layout(local_size_x = 32) in;

layout(std430, binding = 0) readonly buffer Offsets { uint offsets[]; };
layout(std430, binding = 1) readonly buffer Samples { vec2 samples[]; };
layout(std430, binding = 2) readonly buffer SampleRay { uint sampleRay[]; };
layout(std430, binding = 3) readonly buffer Field { vec4 field[]; };
layout(std430, binding = 4) readonly buffer NewOffsets { uint newOffsets[]; };
layout(std430, binding = 5) writeonly buffer NewSamples { vec2 newSamples[]; };
layout(std430, binding = 6) writeonly buffer NewSampleRay { uint newSampleRay[]; };
layout(std430, binding = 7) writeonly buffer NewField { vec4 newField[]; };

layout(push_constant) uniform Push {
  uint numRays;
} pc;

void main() {
  uint ray = flatIndex(32u);
  if (ray >= pc.numRays) return;
  uint src = offsets[ray], dst = newOffsets[ray], end = newOffsets[ray + 1u];
  for (; dst < end; ++dst, ++src) {
    newSamples[dst] = samples[src];
    newSampleRay[dst] = sampleRay[src];
    newField[dst] = field[src];
  }
}

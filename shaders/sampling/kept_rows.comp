#version 450
#extension GL_GOOGLE_include_directive : require
// The samples each ray kept before early termination, packed: ray r's first kept[r] marched samples
// (from rayOffsets[r] on) become rows keptOffsets[r] .. keptOffsets[r + 1] of the packed batch, in
// order. Each packed row gets the marched row it came from (the backward reads the forward's rows
// through it, shaders/gpu/row_gather.glsl) and that sample's position (the hash-grid backward reads
// them packed).
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer RayOffsets { uint rayOffsets[]; };    // numRays + 1, marched
layout(std430, binding = 1) readonly buffer KeptOffsets { uint keptOffsets[]; };  // numRays + 1, packed
layout(binding = 2, rgba32f) uniform readonly imageBuffer positions;              // per marched sample
layout(std430, binding = 3) writeonly buffer Rows { uint rows[]; };
layout(std430, binding = 4) writeonly buffer KeptPositions { vec4 keptPositions[]; };

#include "sampling/kept_rows_shared.h"

void main() {
  uint ray = gl_GlobalInvocationID.x;
  if (ray >= pc.numRays) return;
  uint from = rayOffsets[ray], to = keptOffsets[ray], end = keptOffsets[ray + 1u];
  for (uint i = to; i < end; ++i, ++from) {
    rows[i] = from;
    keptPositions[i] = imageLoad(positions, int(from));
  }
}

#version 450
// The grid's mean density (instant-ngp caps the occupancy threshold at it, so that a young field
// whose densities are all small is not declared empty everywhere), on the device so that an update
// needs no read-back. One workgroup: each lane sums a strided share, then a tree in shared memory;
// no atomics, so the result is the same bits every time. Non-finite densities, and the -1 of a
// cell no training camera sees (occupancy_mark_unseen), count as 0.
#extension GL_GOOGLE_include_directive : require
#include "occupancy/occupancy.glsl"

layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer Density { float gridDensity[]; };
layout(std430, binding = 1) writeonly buffer Mean { float meanDensity; };

#include "occupancy/occupancy_mean_shared.h"

shared float sums[256];

void main() {
  uint l = gl_LocalInvocationID.x;
  float s = 0.0;
  for (uint i = l; i < pc.numCells; i += 256u) {
    float d = gridDensity[i];
    s += isnan(d) || isinf(d) ? 0.0 : max(d, 0.0);
  }
  sums[l] = s;
  barrier();
  for (uint h = 128u; h > 0u; h >>= 1u) {
    if (l < h) sums[l] += sums[l + h];
    barrier();
  }
  if (l == 0u) meanDensity = sums[0] / float(pc.numCells);
}

#version 450
// Occupancy update, step 2: the largest new density seen in each cell this update (several points
// may share a cell in random mode). Densities are >= 0 after sanitising, and non-negative floats
// order like their bit patterns, so an integer atomicMax does it without float atomics.
#extension GL_GOOGLE_include_directive : require
#include "occupancy/occupancy.glsl"

layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer Cells { uint cells[]; };
layout(std430, binding = 1) readonly buffer Density { float density[]; };
layout(std430, binding = 2) buffer Fresh { uint freshBits[]; };  // float bits, zeroed by the host

#include "occupancy/occupancy_splat_shared.h"

void main() {
  uint j = flatIndex(256u);
  if (j >= pc.count) return;
  atomicMax(freshBits[cells[j]], floatBitsToUint(sanitizeDensity(density[j * pc.stride + pc.component])));
}

#version 450
// Occupied cells: popcount of the bit words (bits past the last cell masked off, so a grid marked
// all-occupied by a fill counts right), 16 words per invocation, one atomicAdd each.
#extension GL_GOOGLE_include_directive : require
#include "occupancy/occupancy.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Bits { uint occupancyBits[]; };
layout(std430, binding = 1) buffer Count { uint occupiedCells; };

#include "occupancy/occupancy_count_shared.h"

void main() {
  uint first = flatIndex(64u) * 16u;
  uint numWords = (pc.numCells + 31u) / 32u, n = 0u;
  for (uint w = first; w < min(first + 16u, numWords); ++w) {
    uint valid = min(pc.numCells - w * 32u, 32u);
    uint mask = valid == 32u ? 0xffffffffu : (1u << valid) - 1u;
    n += uint(bitCount(occupancyBits[w] & mask));
  }
  if (n != 0u) atomicAdd(occupiedCells, n);
}

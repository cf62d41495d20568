#version 450
#extension GL_GOOGLE_include_directive : require
// Marching cubes, pass 1b: the triangle count of each cell of the chunk, from its case.
#include "mesh/marching_cubes.glsl"

layout(std430, binding = 0) readonly buffer Grid { float density[]; };
layout(std430, binding = 1) readonly buffer Table { uint table[]; };
layout(std430, binding = 2) writeonly buffer Counts { uint counts[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  uint base = cellSample(pc.first + i), config = 0u;
  for (uint c = 0u; c < 8u; ++c) config |= (insideSurface(density[cornerSample(base, c)]) ? 1u : 0u) << c;
  counts[i] = table[config * kTableStride];
}

#version 450
#extension GL_GOOGLE_include_directive : require
// The density (the field's w) of slots [first, first + count) of the listed blocks into the grid
// (grid_blocks.glsl); slots past the grid's edge are dropped.
#include "mesh/grid_blocks.glsl"

layout(local_size_x = 256) in;

layout(std430, binding = 0) readonly buffer Field { vec4 field[]; };  // rgb, sigma
layout(std430, binding = 1) writeonly buffer Grid { float density[]; };
layout(std430, binding = 2) readonly buffer Blocks { uint blocks[]; };

#include "mesh/grid_density_shared.h"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  uint s = pc.first + i;
  uvec3 idx;
  if (blockSample(blocks[s / (kBlockSide * kBlockSide * kBlockSide)], s, pc.n.xyz, pc.blockCount.xyz, idx))
    density[idx.x + pc.n.x * (idx.y + pc.n.y * idx.z)] = field[i].w;
}

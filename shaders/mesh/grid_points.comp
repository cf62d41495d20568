#version 450
#extension GL_GOOGLE_include_directive : require
// The field's inputs at slots [first, first + count) of the listed blocks (grid_blocks.glsl): the
// sample's world position origin + index * spacing mapped from the scene box onto [-1, 1]^3 (as
// shaders/sampling/sample_points.comp maps a ray's samples). A slot past the grid's edge takes the
// nearest sample's position (evaluated, never stored). Directions are the caller's.
#include "mesh/grid_blocks.glsl"

layout(local_size_x = 256) in;

layout(std430, binding = 0) writeonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) readonly buffer Blocks { uint blocks[]; };

#include "mesh/grid_points_shared.h"
#include "sampling/box_position.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  uint s = pc.first + i;
  uvec3 idx;
  blockSample(blocks[s / (kBlockSide * kBlockSide * kBlockSide)], s, pc.n.xyz, pc.blockCount.xyz, idx);
  idx = min(idx, pc.n.xyz - 1u);
  vec3 x = pc.origin.xyz + pc.spacing.xyz * vec3(idx);
  positions[i] = boxPosition(x, pc.boxMin.xyz, pc.boxMax.xyz);
}

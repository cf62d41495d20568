#version 450
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
// Hash encoding backward, sort-and-reduce step 1 (HashBackwardMode::SortReduce): how many
// contributions (sample, corner) each table entry of the pass receives. Uint atomics only; the
// counts are then prefix-summed into each entry's first slot (scan_blocks.comp / scan_add.comp).
#define HASH_SORT_SAMPLES
#define ROW_LIMIT_BINDING 2  // after the bindings below
#include "encoding/hash_grid.glsl"
#include "encoding/hash_sort.glsl"

layout(local_size_x = 64) in;

#include "encoding/hash_grid_shared.h"

layout(binding = 0, rgba32f) uniform readonly imageBuffer positions;
layout(std430, binding = 1) buffer Counts { uint counts[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (!sortSampleLive(i)) return;
  vec3 p = hashGridContract(imageLoad(positions, int(pc.rowBase + i)).xyz, CONTRACT);
  for (uint l = pc.levelBegin; l < pc.levelEnd; ++l) {
    uint res = pc.res[l / 4u][l % 4u];
    bool dense = ((pc.denseMask >> l) & 1u) != 0u;
    uvec3 cell;
    vec3 w;
    hashGridCell(p, res, cell, w);
    uint base = (l - pc.levelBegin) << LOG2_TABLE;
    [[unroll]] for (uint k = 0u; k < 8u; ++k) {
      uvec3 corner = cell + uvec3(k & 1u, (k >> 1u) & 1u, (k >> 2u) & 1u);
      atomicAdd(counts[base + hashGridIndex(corner, res, dense, LOG2_TABLE)], 1u);
    }
  }
}

#version 450
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
// Hash encoding backward, sort-and-reduce step 2 (HashBackwardMode::SortReduce): each contribution
// (sample, level, corner) writes its entry and weight * dL/dfeature (F floats) into the next free
// slot of its entry's range. `cursor` holds each entry's first slot (the exclusive prefix sum of
// encode_hash_backward_count.comp) and is advanced with a uint atomic, so afterwards cursor[e] is
// the end of entry e's range and cursor[e - 1] its beginning. The order of slots within an entry
// depends on scheduling; encode_hash_backward_reduce.comp sums them order-independently.
#define HASH_SORT_SAMPLES
#define ROW_LIMIT_BINDING 4  // after the bindings below
#include "encoding/hash_grid.glsl"
#include "encoding/hash_sort.glsl"

layout(local_size_x = 64) in;

#include "encoding/hash_grid_shared.h"

layout(binding = 0, rgba32f) uniform readonly imageBuffer positions;
layout(binding = 1, rgba32f) uniform readonly imageBuffer dFeatures;
layout(std430, binding = 2) buffer Cursor { uint cursor[]; };
// A slot is RECORD uvec4s: the entry, then the F values' bits, zero-padded. Whole-uvec4 stores: on
// lavapipe a per-lane store is a scalar loop over the lanes, a uvec4 costing about two floats'.
const uint RECORD = (FEATURES + 4u) / 4u;
layout(std430, binding = 3) writeonly buffer Slots { uvec4 slots[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (!sortSampleLive(i)) return;
  uint row = pc.rowBase + i;
  vec3 p = hashGridContract(imageLoad(positions, int(row)).xyz, CONTRACT);
  uint src = row * pc.strideVec4 + pc.offsetVec4;
  for (uint l = pc.levelBegin; l < pc.levelEnd; ++l) {
    // Level l's F features start at column l * F of the block: within one vec4 for F <= 4, two for F = 8.
    uint col = l * FEATURES;
    vec4 d = imageLoad(dFeatures, int(src + col / 4u));
    vec4 d2 = FEATURES == 8u ? imageLoad(dFeatures, int(src + col / 4u + 1u)) : vec4(0.0);
    uint c0 = col % 4u;
    uint res = pc.res[l / 4u][l % 4u];
    bool dense = ((pc.denseMask >> l) & 1u) != 0u;
    uvec3 cell;
    vec3 w;
    hashGridCell(p, res, cell, w);
    uint base = (l - pc.levelBegin) << LOG2_TABLE;
    [[unroll]] for (uint k = 0u; k < 8u; ++k) {
      uvec3 corner = cell + uvec3(k & 1u, (k >> 1u) & 1u, (k >> 2u) & 1u);
      uint e = base + hashGridIndex(corner, res, dense, LOG2_TABLE);
      float wk = hashGridWeight(k, w);
      uint words[12] = uint[12](e, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u);
      [[unroll]] for (uint f = 0u; f < FEATURES; ++f)
        words[1u + f] = floatBitsToUint(wk * (f < 4u ? d[c0 + f] : d2[f - 4u]));
      uint slot = atomicAdd(cursor[e], 1u);
      [[unroll]] for (uint r = 0u; r < RECORD; ++r)
        slots[slot * RECORD + r] = uvec4(words[4u * r], words[4u * r + 1u], words[4u * r + 2u], words[4u * r + 3u]);
    }
  }
}

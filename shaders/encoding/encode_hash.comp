#version 450
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
// Multiresolution hash encoding, forward: one invocation per sample, L * F trilinearly interpolated
// table features written as whole vec4s into a row-major feature matrix at a 4-aligned column
// offset (the block's last vec4 zero-padded). Layouts: src/core/layouts/hash_grid_layout.h.
// Corners are unrolled. Positions and the table are read through rgba32f texel buffers: on lavapipe
// an imageLoad at per-lane coordinates is a vectorised gather, where an SSBO load is a scalar loop
// over the lanes (shared/LAVAPIPE.md). An entry of F = 2 is half a texel, F = 1 a quarter.
#include "encoding/hash_grid.glsl"
#define ROW_GATHER_BINDING 3
#include "gpu/row_gather.glsl"  // with pc.gather, invocation i encodes row rowGather[i]
#define ROW_LIMIT_BINDING 4
#include "gpu/row_limit.glsl"

layout(local_size_x = 64) in;

#include "encoding/hash_grid_shared.h"
// Levels are processed in groups that fill whole vec4s of output (4 / F levels, or one level of
// two vec4s for F = 8), so every accumulator is a temporary of the loop body: no array indexed
// by a loop counter (lavapipe would spill it to per-lane scratch memory).
const uint GROUP = FEATURES >= 4u ? 1u : 4u / FEATURES;   // levels per group
const uint GROUP_VEC4 = FEATURES == 8u ? 2u : 1u;         // output vec4s per group
const uint GROUPS = (LEVELS + GROUP - 1u) / GROUP;

layout(binding = 0, rgba32f) uniform readonly imageBuffer positions;
layout(binding = 1, rgba32f) uniform readonly imageBuffer table;
layout(std430, binding = 2) writeonly buffer Features { vec4 features[]; };

#include "encoding/encode_hash_shared.h"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= limitedRows(pc.count, pc.limitBase)) return;
  uint row = gatheredRow(i, pc.gather);
  vec3 p = hashGridContract(imageLoad(positions, int(row)).xyz, CONTRACT);
  uint dst = row * pc.strideVec4 + pc.offsetVec4;
  for (uint g = 0u; g < GROUPS; ++g) {
    vec4 acc = vec4(0.0), acc2 = vec4(0.0);
    [[unroll]] for (uint lg = 0u; lg < GROUP; ++lg) {
      uint l = g * GROUP + lg;
      if (l < LEVELS) {  // a partial last group leaves its vec4 zero-padded
        uint res = pc.res[l / 4u][l % 4u];
        bool dense = ((pc.denseMask >> l) & 1u) != 0u;
        uvec3 cell;
        vec3 w;
        hashGridCell(p, res, cell, w);
        [[unroll]] for (uint k = 0u; k < 8u; ++k) {
          uvec3 corner = cell + uvec3(k & 1u, (k >> 1u) & 1u, (k >> 2u) & 1u);
          uint entry = (l << LOG2_TABLE) + hashGridIndex(corner, res, dense, LOG2_TABLE);
          float wk = hashGridWeight(k, w);
          if (FEATURES == 1u) {
            acc[lg] += wk * imageLoad(table, int(entry >> 2u))[entry & 3u];
          } else if (FEATURES == 2u) {
            vec4 t = imageLoad(table, int(entry >> 1u));
            vec2 e = (entry & 1u) != 0u ? t.zw : t.xy;
            acc[2u * lg] += wk * e.x;
            acc[2u * lg + 1u] += wk * e.y;
          } else if (FEATURES == 4u) {
            acc += wk * imageLoad(table, int(entry));
          } else {
            acc += wk * imageLoad(table, int(2u * entry));
            acc2 += wk * imageLoad(table, int(2u * entry + 1u));
          }
        }
      }
    }
    features[dst + g * GROUP_VEC4] = acc;
    if (GROUP_VEC4 == 2u) features[dst + g * GROUP_VEC4 + 1u] = acc2;
  }
}

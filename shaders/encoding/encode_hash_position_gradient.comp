#version 450
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
// Multiresolution hash encoding, backward to the position: one invocation per sample writes
// dL/dp = sum over levels and features of dL/dfeature * d feature / d p (p in [-1, 1]^3, as the
// forward reads it; encoding/hash_position_gradient.glsl), the gradient camera refinement carries
// on to the rays. Table and inputs are read as encode_hash.comp reads them. On its own where the
// table's backward sorts (HashBackwardMode::SortReduce); else encode_hash_backward_position.comp
// computes it in the table's backward pass.
#include "encoding/hash_grid.glsl"
#define ROW_LIMIT_BINDING 4
#include "gpu/row_limit.glsl"

layout(local_size_x = 64) in;

#include "encoding/hash_grid_shared.h"
const uint GROUP = FEATURES >= 4u ? 1u : 4u / FEATURES;
const uint GROUP_VEC4 = FEATURES == 8u ? 2u : 1u;
const uint GROUPS = (LEVELS + GROUP - 1u) / GROUP;

layout(binding = 0, rgba32f) uniform readonly imageBuffer positions;
layout(binding = 1, rgba32f) uniform readonly imageBuffer dFeatures;
layout(binding = 2, rgba32f) uniform readonly imageBuffer table;
layout(std430, binding = 3) writeonly buffer PositionGradient { vec4 dPositions[]; };

#include "encoding/encode_hash_shared.h"

#include "encoding/hash_position_gradient.glsl"

void main() {
  uint row = gl_GlobalInvocationID.x;
  if (row >= limitedRows(pc.count, pc.limitBase)) return;
  vec3 box = imageLoad(positions, int(row)).xyz, p = hashGridContract(box, CONTRACT);
  uint src = row * pc.strideVec4 + pc.offsetVec4;
  vec3 grad = vec3(0.0);
  for (uint g = 0u; g < GROUPS; ++g) {
    vec4 d = imageLoad(dFeatures, int(src + g * GROUP_VEC4));
    vec4 d2 = GROUP_VEC4 == 2u ? imageLoad(dFeatures, int(src + g * GROUP_VEC4 + 1u)) : vec4(0.0);
    if (all(equal(d, vec4(0.0))) && all(equal(d2, vec4(0.0)))) continue;  // behind a ray's cut
    [[unroll]] for (uint lg = 0u; lg < GROUP; ++lg) {
      uint l = g * GROUP + lg;
      if (l < LEVELS) {
        uint res = pc.res[l / 4u][l % 4u];
        bool dense = ((pc.denseMask >> l) & 1u) != 0u;
        uvec3 cell;
        vec3 w;
        hashGridCell(p, res, cell, w);
        vec3 dw = vec3(0.0);  // dL/dw
        [[unroll]] for (uint k = 0u; k < 8u; ++k) {
          uvec3 corner = cell + uvec3(k & 1u, (k >> 1u) & 1u, (k >> 2u) & 1u);
          uint entry = (l << LOG2_TABLE) + hashGridIndex(corner, res, dense, LOG2_TABLE);
          dw += hashEntryDot(entry, lg, d, d2) * hashCornerSlope(k, w);
        }
        grad += dw * (0.5 * float(res));
      }
    }
  }
  dPositions[row] = vec4(hashGridContractGradient(box, CONTRACT, hashClampedGradient(p, grad)), 0.0);
}

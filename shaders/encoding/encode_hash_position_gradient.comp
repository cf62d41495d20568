#version 450
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
// Multiresolution hash encoding, backward to the position: one invocation per sample writes
// dL/dp = sum over levels and features of dL/dfeature * d feature / d p (p in [-1, 1]^3, as the
// forward reads it), the gradient camera refinement carries on to the rays. Within a cell a feature
// is trilinear in the cell coordinate w = (p + 1) / 2 * res - cell, so its derivative along an axis
// is the difference of the corner values weighted by the other two axes' weights, times res / 2.
// Outside the grid the forward clamps p, which makes the feature flat there: dL/dp = 0 on that axis.
// Table and inputs are read as encode_hash.comp reads them.
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

// dL/dfeatures of level lg of the group (d, d2) dotted with the table entry's features.
float entryDot(uint entry, uint lg, vec4 d, vec4 d2) {
  if (FEATURES == 1u) return d[lg] * imageLoad(table, int(entry >> 2u))[entry & 3u];
  if (FEATURES == 2u) {
    vec4 t = imageLoad(table, int(entry >> 1u));
    vec2 e = (entry & 1u) != 0u ? t.zw : t.xy;
    return d[2u * lg] * e.x + d[2u * lg + 1u] * e.y;
  }
  if (FEATURES == 4u) return dot(d, imageLoad(table, int(entry)));
  return dot(d, imageLoad(table, int(2u * entry))) + dot(d2, imageLoad(table, int(2u * entry + 1u)));
}

void main() {
  uint row = gl_GlobalInvocationID.x;
  if (row >= limitedRows(pc.count, pc.limitBase)) return;
  vec3 p = imageLoad(positions, int(row)).xyz;
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
          float e = entryDot((l << LOG2_TABLE) + hashGridIndex(corner, res, dense, LOG2_TABLE), lg, d, d2);
          vec3 s = vec3((k & 1u) != 0u ? 1.0 : -1.0, (k & 2u) != 0u ? 1.0 : -1.0, (k & 4u) != 0u ? 1.0 : -1.0);
          float wx = (k & 1u) != 0u ? w.x : 1.0 - w.x;
          float wy = (k & 2u) != 0u ? w.y : 1.0 - w.y;
          float wz = (k & 4u) != 0u ? w.z : 1.0 - w.z;
          dw += e * s * vec3(wy * wz, wx * wz, wx * wy);
        }
        grad += dw * (0.5 * float(res));
      }
    }
  }
  // The clamp in hashGridCell: flat outside [-1, 1] on each axis.
  grad *= vec3(greaterThan(p, vec3(-1.0))) * vec3(lessThan(p, vec3(1.0)));
  dPositions[row] = vec4(grad, 0.0);
}

#version 450
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
// Multiresolution hash encoding, forward: one invocation per sample, L * F trilinearly interpolated
// table features written as whole vec4s into a row-major feature matrix at a 4-aligned column
// offset (the block's last vec4 zero-padded). Layouts: src/reference/hash_encoding.h.
// Levels and corners are unrolled (loop-carried accumulators are masked writes on lavapipe);
// positions come through a texel buffer (vectorised loads), table entries of F = 2 as vec2 loads
// (half the per-float cost of scalar gathers).
#include "hash_grid.glsl"

layout(local_size_x = 64) in;

layout(constant_id = 0) const uint LEVELS = 16u;
layout(constant_id = 1) const uint FEATURES = 2u;     // 1, 2, 4 or 8
layout(constant_id = 2) const uint LOG2_TABLE = 19u;
const uint OUT_DIMS = LEVELS * FEATURES;
const uint OUT_VEC4 = (OUT_DIMS + 3u) / 4u;
const uint PAIRS = FEATURES / 2u;                     // vec2 loads per entry (F >= 2)

layout(binding = 0, rgba32f) uniform readonly imageBuffer positions;
layout(std430, binding = 1) readonly buffer Table { float table[]; };
layout(std430, binding = 1) readonly buffer Table2 { vec2 table2[]; };  // same buffer, vec2 view
layout(std430, binding = 2) writeonly buffer Features { vec4 features[]; };

layout(push_constant) uniform Push {
  uint count;        // rows
  uint strideVec4;   // row stride in vec4s
  uint offsetVec4;   // first column / 4
  uint denseMask;    // bit l: level l is densely indexed
  uvec4 res[6];      // resolution of level l at res[l / 4][l % 4]
} pc;

void main() {
  uint row = gl_GlobalInvocationID.x;
  if (row >= pc.count) return;
  vec3 p = imageLoad(positions, int(row)).xyz;
  float v[OUT_VEC4 * 4u];
  [[unroll]] for (uint j = 0u; j < OUT_VEC4 * 4u; ++j) v[j] = 0.0;
  [[unroll]] for (uint l = 0u; l < LEVELS; ++l) {
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
        v[l] += wk * table[entry];
      } else {
        [[unroll]] for (uint q = 0u; q < PAIRS; ++q) {
          vec2 t = table2[entry * PAIRS + q];
          v[l * FEATURES + 2u * q] += wk * t.x;
          v[l * FEATURES + 2u * q + 1u] += wk * t.y;
        }
      }
    }
  }
  uint dst = row * pc.strideVec4 + pc.offsetVec4;
  [[unroll]] for (uint j = 0u; j < OUT_VEC4; ++j)
    features[dst + j] = vec4(v[4u * j], v[4u * j + 1u], v[4u * j + 2u], v[4u * j + 3u]);
}

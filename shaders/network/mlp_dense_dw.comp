#version 450
// One dense layer, backward to its weights: G[k][n] += sum_rows X[row][k] dZ[row][n] for the
// columns n in [N0, N0 + NW) of a [K4][N4] block at float offset GOFF of the gradient buffer.
// X is one input part (A or B) of the layer, or the constant 1 (ONES: the bias row, K4 = KT = 1).
// The gradient buffer is accumulated into with float atomics: chunks and parts add up.
//
// Shaped for lavapipe (shared/LAVAPIPE.md): lanes are rows; workgroup y picks a KT x NT tile; each
// invocation sums per-lane outer products over ITERS*U rows (row0 + (it*U + u)*G). The U rows of one
// iteration are summed in loop-local temporaries so the loop-carried accumulators (masked writes in
// llvmpipe) are touched once per U rows. Then subgroupAdd and one atomicAdd per subgroup and entry.
#extension GL_EXT_control_flow_attributes : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_EXT_shader_atomic_float : require
#extension GL_GOOGLE_include_directive : require

#include "network/mlp_dense_dw_shared.h"

layout(binding = 0, rgba32f) uniform readonly imageBuffer X;
layout(binding = 1, rgba32f) uniform readonly imageBuffer DZ;
layout(std430, binding = 2) buffer Grads { float g[]; };
#define ROW_GATHER_BINDING 3
#include "gpu/row_gather.glsl"  // X (the forward's activations) at the gathered rows
#define ROW_LIMIT_BINDING 4
#include "gpu/row_limit.glsl"

void main() {
  uint G = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  uint row0 = gl_GlobalInvocationID.x;
  // Under a device row limit the rows at and past it add nothing: a lane with none left leaves (the
  // rest of its subgroup reduces without it), the others stop sweeping after the last live row.
  uint count = limitedRows(pc.count, pc.limitBase);
  if (row0 >= count) return;
  uint iters = min(pc.iters, (count + U * G - 1u) / (U * G));
  uint tile = gl_WorkGroupID.y, ntn = NW / NT;
  uint k0 = (tile / ntn) * KT, n0 = N0 + (tile % ntn) * NT;
  float acc[KT][NT];
  [[unroll]] for (uint i = 0; i < KT; i++)
    [[unroll]] for (uint j = 0; j < NT; j++) acc[i][j] = 0.0;
  for (uint it = 0; it < iters; it++) {
    float x[U][KT], d[U][NT];
    [[unroll]] for (uint u = 0; u < U; u++) {
      uint b = row0 + (it * U + u) * G;
      uint bc = min(b, count - 1u);
      float valid = b < count ? 1.0 : 0.0;
      if (ONES) {
        x[u][0] = valid;
      } else {
        uint bx = gatheredRow(bc, pc.gather);
        [[unroll]] for (uint q = 0; q < KT / 4u; q++) {
          vec4 v = imageLoad(X, int(bx * pc.strideX4 + k0 / 4u + q)) * valid;
          x[u][4 * q] = v.x; x[u][4 * q + 1] = v.y; x[u][4 * q + 2] = v.z; x[u][4 * q + 3] = v.w;
        }
      }
      [[unroll]] for (uint q = 0; q < NT / 4u; q++) {
        vec4 v = imageLoad(DZ, int(bc * pc.strideZ4 + n0 / 4u + q));
        d[u][4 * q] = v.x; d[u][4 * q + 1] = v.y; d[u][4 * q + 2] = v.z; d[u][4 * q + 3] = v.w;
      }
    }
    [[unroll]] for (uint i = 0; i < KT; i++)
      [[unroll]] for (uint j = 0; j < NT; j++) {
        float t = x[0][i] * d[0][j];
        [[unroll]] for (uint u = 1; u < U; u++) t += x[u][i] * d[u][j];
        acc[i][j] += t;
      }
  }
  // The reduction runs once per invocation: a dynamic loop keeps its code (and the JIT time of
  // KT*NT subgroupAdds, each a loop over the lanes in llvmpipe) small.
  float sums[KT * NT];
  [[unroll]] for (uint i = 0; i < KT; i++)
    [[unroll]] for (uint j = 0; j < NT; j++) sums[i * NT + j] = acc[i][j];
  [[dont_unroll]] for (uint e = 0; e < KT * NT; e++) {
    float s = subgroupAdd(sums[e]);
    if (subgroupElect()) atomicAdd(g[GOFF + (k0 + e / NT) * N4 + n0 + e % NT], s);
  }
}

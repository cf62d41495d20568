#version 450
// One dense layer, forward: Y = act(concat(A, B) W + bias (+ the row's bias)) for `count` rows. W is
// row-major [KA4 + KB4][N4] at vec4 offset WOFF4 of the parameter buffer, the bias [N4] right after
// it; ROW_BIAS: a bias per row too (network/row_bias.glsl).
//
// Shaped for lavapipe (shared/LAVAPIPE.md): lanes are rows, each invocation owns R rows
// (row0 + r*G) kept in registers; the k loop is fully unrolled so every weight is read with a
// uniform imageLoad (one branch-free broadcast reused by R rows); the loop over output blocks of NB
// columns stays dynamic: unrolling it as well (every weight coordinate a constant) measured no faster
// once 4 columns are summed per accumulator update (DENSE_K4), and it cost ~9 s of JIT per 64x64
// layer. A tail of 4-wide blocks covers (N4 - N_FIRST) % NB. Rows past `count` read the last row and store
// nothing. With pc.gather, row i of the batch is row rowGather[i] of A, B, Y and the row bias (a
// training forward over the samples in front of early termination, src/nerf/sampling/segment_rows.h).
// N_FIRST: only the columns from it on are computed and stored (a proposal's feature layer, whose
// sigma column alone is read: the columns before keep what they held).
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "network/mlp_common.glsl"

#include "network/mlp_dense_shared.h"

layout(binding = 0, rgba32f) uniform readonly imageBuffer A;
layout(binding = 1, rgba32f) uniform readonly imageBuffer B;
layout(binding = 2, rgba32f) uniform readonly imageBuffer P;
layout(std430, binding = 3) writeonly buffer Y { vec4 y4[]; };
#include "network/dense_block.glsl"  // after R and P
#define ROW_BIAS_BINDING 4
#include "network/row_bias.glsl"
#define ROW_GATHER_BINDING 7
#include "gpu/row_gather.glsl"
#define ROW_LIMIT_BINDING 8
#include "gpu/row_limit.glsl"

const uint NMAIN = N4 - (N4 - N_FIRST) % NB;

// acc[r][j] = bias + sum_k x[r][k] W[k][n0 + j] for j < BLK, then activation and store.
#define DENSE_BLOCK(BLK, n0)                                                                       \
  {                                                                                                \
    float acc[R][BLK];                                                                             \
    DENSE_ACCUMULATE(acc, BLK, n0, xa, KA4, xb, KB4, WOFF4, N4)                                    \
    [[unroll]] for (uint r = 0; r < R; r++) {                                                      \
      uint row = row0 + r * G;                                                                     \
      if (row < count)                                                                          \
        [[unroll]] for (uint j = 0; j < BLK; j += 4) {                                             \
          uint col = (n0) + j;                                                                     \
          vec4 z = vec4(acc[r][j], acc[r][j + 1], acc[r][j + 2], acc[r][j + 3]);                   \
          if (ROW_BIAS != ROW_BIAS_NONE) z += rowBias(biasRow[r], col / 4u, N4);                   \
          vec4 v = mlpActivate(ACT, z);                                                            \
          if (col + 4u > NTRUE) v = mix(vec4(0.0), v, lessThan(uvec4(col) + uvec4(0, 1, 2, 3), uvec4(NTRUE))); \
          y4[rows[r] * pc.strideY4 + col / 4u] = v;                                                \
        }                                                                                          \
    }                                                                                              \
  }

void main() {
  uint row0 = gl_GlobalInvocationID.x;
  uint count = limitedRows(pc.count, pc.limitBase);
  uint G = denseRowStride(count, pc.count);
  if (row0 >= G) return;
  float xa[R][KA4];
  float xb[R][KB4 > 0u ? KB4 : 1u];
  uint rows[R], biasRow[R];
  [[unroll]] for (uint r = 0; r < R; r++) {
    rows[r] = gatheredRow(min(row0 + r * G, count - 1u), pc.gather);
    DENSE_LOAD_ROW(xa, r, A, KA4, pc.strideA4, rows[r])
    DENSE_LOAD_ROW(xb, r, B, KB4, pc.strideB4, rows[r])
    biasRow[r] = ROW_BIAS != ROW_BIAS_NONE ? rowBiasRow(rows[r]) : 0u;
  }
  [[dont_unroll]] for (uint n0 = N_FIRST; n0 < NMAIN; n0 += NB) DENSE_BLOCK(NB, n0)
  [[dont_unroll]] for (uint n0 = NMAIN; n0 < N4; n0 += 4u) DENSE_BLOCK(4u, n0)
}

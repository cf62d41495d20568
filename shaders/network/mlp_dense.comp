#version 450
// One dense layer, forward: Y = act(concat(A, B) W + bias) for `count` rows. W is row-major
// [KA4 + KB4][N4] at vec4 offset WOFF4 of the parameter buffer, the bias [N4] right after it.
//
// Shaped for lavapipe (shared/LAVAPIPE.md): lanes are rows, each invocation owns R rows
// (row0 + r*G) kept in registers; the k loop is fully unrolled so every weight is read with a
// uniform imageLoad (one branch-free broadcast reused by R rows); the loop over output blocks of NB
// columns stays dynamic: unrolling it as well (every weight coordinate a constant) measured no faster
// once 4 columns are summed per accumulator update (DENSE_K4), and it cost ~9 s of JIT per 64x64
// layer. A tail of 4-wide blocks covers N4 % NB. Rows past `count` read the last row and store
// nothing.
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "network/mlp_common.glsl"

layout(local_size_x_id = 0) in;
layout(constant_id = 1) const uint KA4 = 64;     // padded width of input A
layout(constant_id = 2) const uint KB4 = 0;      // padded width of input B (0: none)
layout(constant_id = 3) const uint N4 = 64;      // padded output width
layout(constant_id = 4) const uint NTRUE = 64;   // output columns >= NTRUE are stored as 0
layout(constant_id = 5) const uint ACT = 1;      // MLP_ACT_*
layout(constant_id = 6) const uint WOFF4 = 0;    // vec4 offset of W in the parameter buffer
layout(constant_id = 7) const uint R = 4;        // rows per invocation
layout(constant_id = 8) const uint NB = 8;       // output columns per block (multiple of 4)

layout(binding = 0, rgba32f) uniform readonly imageBuffer A;
layout(binding = 1, rgba32f) uniform readonly imageBuffer B;
layout(binding = 2, rgba32f) uniform readonly imageBuffer P;
layout(std430, binding = 3) writeonly buffer Y { vec4 y4[]; };
#define ROW_LIMIT_BINDING 4
#include "gpu/row_limit.glsl"

layout(push_constant) uniform Push {
  uint count;
  uint strideA4, strideB4, strideY4;  // row strides in vec4
  uint limitBase;                     // row_limit.glsl
} pc;

const uint K4 = KA4 + KB4;
const uint NMAIN = N4 - N4 % NB;
const uint BOFF4 = WOFF4 + K4 * N4 / 4u;

// Four input columns at a time: their products are summed before touching the accumulator, so
// the (spilled) accumulators are loaded and stored once per 4 columns instead of once per column.
#define DENSE_K4(XARR, k, wrow, n0, j)                                                                \
  {                                                                                                \
    vec4 w0 = imageLoad(P, int(WOFF4 + ((wrow) * N4 + (n0) + (j)) / 4u));                          \
    vec4 w1 = imageLoad(P, int(WOFF4 + ((wrow + 1u) * N4 + (n0) + (j)) / 4u));                     \
    vec4 w2 = imageLoad(P, int(WOFF4 + ((wrow + 2u) * N4 + (n0) + (j)) / 4u));                     \
    vec4 w3 = imageLoad(P, int(WOFF4 + ((wrow + 3u) * N4 + (n0) + (j)) / 4u));                     \
    [[unroll]] for (uint r = 0; r < R; r++) {                                                      \
      vec4 t = XARR[r][k] * w0 + XARR[r][k + 1] * w1 + XARR[r][k + 2] * w2 + XARR[r][k + 3] * w3;  \
      acc[r][j] += t.x; acc[r][j + 1] += t.y; acc[r][j + 2] += t.z; acc[r][j + 3] += t.w;          \
    }                                                                                              \
  }

// acc[r][j] = bias + sum_k x[r][k] W[k][n0 + j] for j < BLK, then activation and store.
#define DENSE_BLOCK(BLK, n0)                                                                       \
  {                                                                                                \
    float acc[R][BLK];                                                                             \
    [[unroll]] for (uint j = 0; j < BLK; j += 4) {                                                 \
      vec4 b4 = imageLoad(P, int(BOFF4 + ((n0) + j) / 4u));                                        \
      [[unroll]] for (uint r = 0; r < R; r++) {                                                    \
        acc[r][j] = b4.x; acc[r][j + 1] = b4.y; acc[r][j + 2] = b4.z; acc[r][j + 3] = b4.w;        \
      }                                                                                            \
    }                                                                                              \
    [[unroll]] for (uint k = 0; k < KA4; k += 4)                                                   \
      [[unroll]] for (uint j = 0; j < BLK; j += 4) DENSE_K4(xa, k, k, n0, j)                       \
    [[unroll]] for (uint k = 0; k < KB4; k += 4)                                                   \
      [[unroll]] for (uint j = 0; j < BLK; j += 4) DENSE_K4(xb, k, KA4 + k, n0, j)                 \
    [[unroll]] for (uint r = 0; r < R; r++) {                                                      \
      uint row = row0 + r * G;                                                                     \
      if (row < count)                                                                          \
        [[unroll]] for (uint j = 0; j < BLK; j += 4) {                                             \
          vec4 v = mlpActivate(ACT, vec4(acc[r][j], acc[r][j + 1], acc[r][j + 2], acc[r][j + 3])); \
          uint col = (n0) + j;                                                                     \
          if (col + 4u > NTRUE) v = mix(vec4(0.0), v, lessThan(uvec4(col) + uvec4(0, 1, 2, 3), uvec4(NTRUE))); \
          y4[row * pc.strideY4 + col / 4u] = v;                                                    \
        }                                                                                          \
    }                                                                                              \
  }

void main() {
  uint G = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  uint row0 = gl_GlobalInvocationID.x;
  uint count = limitedRows(pc.count, pc.limitBase);
  // Under a device row limit only the invocations that the limited rows need run, R rows each,
  // strided by their own count (the dispatch is indirect, sized for the limit, or direct, for the
  // whole batch).
  if (count < pc.count) G = min(G, (((count + R - 1u) / R) + gl_WorkGroupSize.x - 1u) / gl_WorkGroupSize.x * gl_WorkGroupSize.x);
  if (row0 >= G) return;
  float xa[R][KA4];
  float xb[R][KB4 > 0u ? KB4 : 1u];
  [[unroll]] for (uint r = 0; r < R; r++) {
    uint row = min(row0 + r * G, count - 1u);
    [[unroll]] for (uint q = 0; q < KA4 / 4u; q++) {
      vec4 v = imageLoad(A, int(row * pc.strideA4 + q));
      xa[r][4 * q] = v.x; xa[r][4 * q + 1] = v.y; xa[r][4 * q + 2] = v.z; xa[r][4 * q + 3] = v.w;
    }
    [[unroll]] for (uint q = 0; q < KB4 / 4u; q++) {
      vec4 v = imageLoad(B, int(row * pc.strideB4 + q));
      xb[r][4 * q] = v.x; xb[r][4 * q + 1] = v.y; xb[r][4 * q + 2] = v.z; xb[r][4 * q + 3] = v.w;
    }
  }
  [[dont_unroll]] for (uint n0 = 0; n0 < NMAIN; n0 += NB) DENSE_BLOCK(NB, n0)
  [[dont_unroll]] for (uint n0 = NMAIN; n0 < N4; n0 += 4u) DENSE_BLOCK(4u, n0)
}

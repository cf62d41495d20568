#version 450
// One dense layer, backward to its inputs: dX = dZ W^T for `count` rows, split into the A part
// (columns [0, KA4) of X) and the B part ([KA4, KA4 + KB4)). dZ is dL/d(pre-activation).
//   MODE_A / MODE_B: 0 skip, 1 store, 2 store times [A > 0] (the ReLU derivative of the layer that
//   produced A, so the result is already the previous layer's dZ), 3 add to what is there.
//   KB_FIRST: the B part's columns before it are neither computed nor written (an appearance
//   vector beside SH(d) needs its own columns' gradient, not the direction's).
//   N_FIRST: dZ's columns before it are not read, as if 0 (a proposal's feature layer, whose sigma
//   column alone has a gradient).
// Same shape as mlp_dense.comp: lanes are rows, R rows per invocation with dZ in registers, the n
// loop unrolled with uniform weight reads, a dynamic loop over blocks of KBLK input columns.
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require

#include "network/mlp_dense_dx_shared.h"

layout(binding = 0, rgba32f) uniform readonly imageBuffer DZ;
layout(binding = 1, rgba32f) uniform readonly imageBuffer A;  // for MODE_A == 2
layout(binding = 2, rgba32f) uniform readonly imageBuffer P;
layout(std430, binding = 3) buffer DA { vec4 da4[]; };
layout(std430, binding = 4) buffer DB { vec4 db4[]; };
#include "network/dense_block.glsl"  // after R and P
#define ROW_GATHER_BINDING 5
#include "gpu/row_gather.glsl"  // A (the forward's activations) at the gathered rows
#define ROW_LIMIT_BINDING 6
#include "gpu/row_limit.glsl"

// acc[r][kk] = sum_n dz[r][n] W[ROW0 + k0 + kk][n]
#define DX_BLOCK(BLK, ROW0, k0)                                                                  \
  float acc[R][BLK];                                                                             \
  [[unroll]] for (uint kk = 0; kk < BLK; kk++)                                                   \
    [[unroll]] for (uint r = 0; r < R; r++) acc[r][kk] = 0.0;                                    \
  [[unroll]] for (uint n = N_FIRST; n < N4; n += 4)                                              \
    [[unroll]] for (uint kk = 0; kk < BLK; kk++) {                                               \
      vec4 w4 = imageLoad(P, int(WOFF4 + ((ROW0 + (k0) + kk) * N4 + n) / 4u));                   \
      [[unroll]] for (uint r = 0; r < R; r++)                                                    \
        acc[r][kk] += dz[r][n] * w4.x + dz[r][n + 1] * w4.y + dz[r][n + 2] * w4.z + dz[r][n + 3] * w4.w; \
    }

void main() {
  uint row0 = gl_GlobalInvocationID.x;
  // The rows past a device row limit are left untouched.
  uint count = limitedRows(pc.count, pc.limitBase);
  uint G = denseRowStride(count, pc.count);
  if (row0 >= G || count == 0u) return;
  float dz[R][N4];
  [[unroll]] for (uint r = 0; r < R; r++)
    DENSE_LOAD_ROW_FROM(dz, r, DZ, N_FIRST, N4, pc.strideZ4, min(row0 + r * G, count - 1u))
  if (MODE_A != 0u) {
    uint arow[R];  // the rows of A (read for the ReLU mask only)
    [[unroll]] for (uint r = 0; r < R; r++)
      arow[r] = MODE_A == 2u ? gatheredRow(min(row0 + r * G, count - 1u), pc.gather) : 0u;
    [[dont_unroll]] for (uint k0 = 0; k0 < KA4; k0 += KBLK) {
      DX_BLOCK(KBLK, 0u, k0)
      [[unroll]] for (uint r = 0; r < R; r++) {
        uint row = row0 + r * G;
        if (row < count)
          [[unroll]] for (uint kk = 0; kk < KBLK; kk += 4) {
            vec4 v = vec4(acc[r][kk], acc[r][kk + 1], acc[r][kk + 2], acc[r][kk + 3]);
            uint i = row * pc.strideDA4 + (k0 + kk) / 4u;
            if (MODE_A == 2u)
              v *= vec4(greaterThan(imageLoad(A, int(arow[r] * pc.strideA4 + (k0 + kk) / 4u)), vec4(0.0)));
            if (MODE_A == 3u) v += da4[i];
            da4[i] = v;
          }
      }
    }
  }
  if (MODE_B != 0u) {
    [[dont_unroll]] for (uint k0 = KB_FIRST; k0 < KB4; k0 += 4u) {
      DX_BLOCK(4u, KA4, k0)
      [[unroll]] for (uint r = 0; r < R; r++) {
        uint row = row0 + r * G;
        if (row < count) {
          vec4 v = vec4(acc[r][0], acc[r][1], acc[r][2], acc[r][3]);
          uint i = row * pc.strideDB4 + k0 / 4u;
          if (MODE_B == 3u) v += db4[i];
          db4[i] = v;
        }
      }
    }
  }
}

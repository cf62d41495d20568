#version 450
// The whole NeRF MLP forward in one kernel, for narrow networks without a skip connection (the fast
// model's): trunk (DEPTH <= 2 layers of W, ReLU) -> feature + sigma (V + 1, no activation) ->
// colour (concat(feature, dir) -> W/2, ReLU; ROW_BIAS: plus a bias per row before the ReLU,
// network/row_bias.glsl) -> head (3, sigmoid), out = vec4(rgb, density(sigma)).
// The same arithmetic as mlp_dense.comp + mlp_nerf_head.comp layer by layer (dense_block.glsl,
// the same order of sums), but every activation stays in registers: nothing is written between
// layers and nothing read back, and the network costs one dispatch instead of DEPTH + 3.
// KEEP = 1 also stores the activations the backward pass reads (NerfMlp::Workspace: the trunk
// outputs, the feature + sigma pre-activation, the colour hidden layer), as the layered path does.
//
// Layouts: src/core/layouts/mlp_layout.h (NerfShape). Rows past `count` (row_limit.glsl cuts it on the
// device) read the last row: they store no output, and what they keep is the last row's again.
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "network/mlp_common.glsl"

#include "network/mlp_nerf_fused_shared.h"

layout(binding = 0, rgba32f) uniform readonly imageBuffer Pos;
layout(binding = 1, rgba32f) uniform readonly imageBuffer Dir;
layout(binding = 2, rgba32f) uniform readonly imageBuffer P;
layout(std430, binding = 3) writeonly buffer Out { vec4 out4[]; };
// KEEP: rows of W (each trunk layer), V + 4 (feature + sigma pre-activation) and W/2 (colour hidden)
layout(std430, binding = 4) writeonly buffer H0 { vec4 h0Kept[]; };
layout(std430, binding = 5) writeonly buffer H1 { vec4 h1Kept[]; };
layout(std430, binding = 6) writeonly buffer F { vec4 fKept[]; };
layout(std430, binding = 7) writeonly buffer C { vec4 cKept[]; };
#include "network/dense_block.glsl"  // after R and P
#define ROW_BIAS_BINDING 8
#include "network/row_bias.glsl"
#define ROW_LIMIT_BINDING 11
#include "gpu/row_limit.glsl"

const uint V4 = V + 4u;   // the feature layer's padded output: V features, sigma, 3 zero columns
const uint W2 = W / 2u;

// Columns per block for a layer N wide: NB where it divides N, else 8 or 4.
#define FUSED_BLOCK_FOR(N) ((N) % NB == 0u ? NB : ((N) % 8u == 0u ? 8u : 4u))

// YOUT[r][n] = act(concat(XA, XB) W + bias)[n] for every output column n < N4 (ACT: MLP_ACT_NONE or
// MLP_ACT_RELU), a block of columns at a time. UNROLL: the block loop is unrolled, so that every
// register index is a constant (the faster code on lavapipe, and the longer compile); otherwise the
// blocks index the output by a uniform loop counter.
#define FUSED_BLOCK(YOUT, N4, BLK, n0, XA, KA4, XB, KB4, WOFF4, ACT)                              \
  {                                                                                              \
    float acc[R][BLK];                                                                           \
    DENSE_ACCUMULATE(acc, BLK, n0, XA, KA4, XB, KB4, WOFF4, N4)                                  \
    [[unroll]] for (uint r = 0; r < R; r++)                                                      \
      [[unroll]] for (uint j = 0; j < (BLK); j++)                                                \
        YOUT[r][(n0) + j] = (ACT) == MLP_ACT_RELU ? max(acc[r][j], 0.0) : acc[r][j];             \
  }
#define FUSED_LAYER(YOUT, N4, XA, KA4, XB, KB4, WOFF4, ACT)                                       \
  if (UNROLL != 0u) {                                                                            \
    [[unroll]] for (uint n0_ = 0; n0_ < (N4); n0_ += FUSED_BLOCK_FOR(N4))                        \
      FUSED_BLOCK(YOUT, N4, FUSED_BLOCK_FOR(N4), n0_, XA, KA4, XB, KB4, WOFF4, ACT)              \
  } else {                                                                                       \
    [[dont_unroll]] for (uint n0_ = 0; n0_ < (N4); n0_ += FUSED_BLOCK_FOR(N4))                   \
      FUSED_BLOCK(YOUT, N4, FUSED_BLOCK_FOR(N4), n0_, XA, KA4, XB, KB4, WOFF4, ACT)              \
  }

// Stores Y's K4 columns of the invocation's rows into BUF (K4 / 4 vec4s a row). A row past `count`
// computed the last row from the same inputs: it writes the same values there, with no branch
// around the store.
#define FUSED_KEEP(BUF, Y, K4)                                                                   \
  if (KEEP != 0u)                                                                                \
    [[unroll]] for (uint r = 0; r < R; r++) {                                                    \
      uint row_ = min(row0 + r * G, count - 1u);                                                 \
      [[unroll]] for (uint q = 0; q < (K4) / 4u; q++)                                            \
        BUF[row_ * ((K4) / 4u) + q] = vec4(Y[r][4u * q], Y[r][4u * q + 1u], Y[r][4u * q + 2u], Y[r][4u * q + 3u]); \
    }

void main() {
  uint row0 = gl_GlobalInvocationID.x;
  uint count = limitedRows(pc.count, pc.limitBase);
  uint G = denseRowStride(count, pc.count);
  if (row0 >= G) return;

  float x[R][KP4];
  DENSE_LOAD_ROWS(x, Pos, KP4, pc.strideP4, row0, G, count)
  float h[R][W];
  FUSED_LAYER(h, W, x, KP4, x, 0u, T0OFF4, MLP_ACT_RELU)
  FUSED_KEEP(h0Kept, h, W)
  if (DEPTH == 2u) {
    float h2[R][W];
    FUSED_LAYER(h2, W, h, W, h, 0u, T1OFF4, MLP_ACT_RELU)
    FUSED_KEEP(h1Kept, h2, W)
    [[unroll]] for (uint r = 0; r < R; r++) [[unroll]] for (uint k = 0; k < W; k++) h[r][k] = h2[r][k];
  }
  if (COLOUR == 0u) {
    // The density alone: the feature layer's block of 4 columns from V (sigma and 3 zero padding
    // columns), the same sums in the same order as the whole layer's; the colour is not computed.
    float s[R][4];
    DENSE_ACCUMULATE(s, 4u, V, h, W, h, 0u, FOFF4, V4)
    [[unroll]] for (uint r = 0; r < R; r++) {
      uint row = row0 + r * G;
      if (row < count) out4[row * pc.strideOut4] = vec4(0.0, 0.0, 0.0, mlpDensity(DENSITY, s[r][0]));
    }
    return;
  }
  // The feature layer: V + 4 columns, of which V + 1 are real; the padding weights and biases are
  // zero, so the 3 padding columns come out exactly 0, as the layered path stores them.
  float f[R][V4];
  FUSED_LAYER(f, V4, h, W, h, 0u, FOFF4, MLP_ACT_NONE)
  FUSED_KEEP(fKept, f, V4)

  float d[R][KD4];
  DENSE_LOAD_ROWS(d, Dir, KD4, pc.strideD4, row0, G, count)
  float c[R][W2];
  if (ROW_BIAS == ROW_BIAS_NONE) {
    FUSED_LAYER(c, W2, f, V, d, KD4, COFF4, MLP_ACT_RELU)
  } else {
    FUSED_LAYER(c, W2, f, V, d, KD4, COFF4, MLP_ACT_NONE)
    [[unroll]] for (uint r = 0; r < R; r++) {
      uint t = rowBiasRow(min(row0 + r * G, count - 1u));
      [[unroll]] for (uint q = 0; q < W2 / 4u; q++) {
        vec4 z = vec4(c[r][4u * q], c[r][4u * q + 1u], c[r][4u * q + 2u], c[r][4u * q + 3u]) + rowBias(t, q, W2);
        z = max(z, vec4(0.0));
        c[r][4u * q] = z.x; c[r][4u * q + 1u] = z.y; c[r][4u * q + 2u] = z.z; c[r][4u * q + 3u] = z.w;
      }
    }
  }
  FUSED_KEEP(cKept, c, W2)

  float rgb[R][4];
  DENSE_ACCUMULATE(rgb, 4u, 0u, c, W2, c, 0u, HOFF4, 4u)
  [[unroll]] for (uint r = 0; r < R; r++) {
    uint row = row0 + r * G;
    if (row < count)
      out4[row * pc.strideOut4] =
          vec4(mlpSigmoid(vec4(rgb[r][0], rgb[r][1], rgb[r][2], rgb[r][3])).xyz, mlpDensity(DENSITY, f[r][V]));
  }
}

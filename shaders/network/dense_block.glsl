// One block of a dense layer's outputs for R rows held in registers, shared by mlp_dense.comp (one
// layer a dispatch) and mlp_nerf_fused.comp (the whole network in one), and the row handling of
// the row-parallel MLP kernels (mlp_dense_dx.comp too): lanes are rows, the k loop
// is unrolled so every weight is one uniform imageLoad of the parameter texel buffer P (a
// branch-free broadcast reused by R rows, shared/LAVAPIPE.md), and four input columns are summed
// before touching an accumulator, so (spilled) accumulators are loaded and stored once per 4
// columns instead of once per column.
//
// The including shader declares `P` (rgba32f imageBuffer of the flat parameters, layout in
// src/core/layouts/mlp_layout.h) and the constant `R`. W is row-major [KA4 + KB4][N4] at vec4 offset
// WOFF4, the bias [N4] right after it.
#ifndef VKNERF_DENSE_BLOCK_GLSL
#define VKNERF_DENSE_BLOCK_GLSL

// acc[r][j .. j+4) += x[r][k .. k+4) . W[wrow .. wrow+4)[n0 + j .. n0 + j + 4)
#define DENSE_K4(acc, X, k, wrow, n0, j, WOFF4, N4)                                               \
  {                                                                                              \
    vec4 w0_ = imageLoad(P, int((WOFF4) + ((wrow) * (N4) + (n0) + (j)) / 4u));                      \
    vec4 w1_ = imageLoad(P, int((WOFF4) + (((wrow) + 1u) * (N4) + (n0) + (j)) / 4u));               \
    vec4 w2_ = imageLoad(P, int((WOFF4) + (((wrow) + 2u) * (N4) + (n0) + (j)) / 4u));               \
    vec4 w3_ = imageLoad(P, int((WOFF4) + (((wrow) + 3u) * (N4) + (n0) + (j)) / 4u));               \
    [[unroll]] for (uint r_ = 0; r_ < R; r_++) {                                                 \
      vec4 t_ = X[r_][k] * w0_ + X[r_][(k) + 1u] * w1_ + X[r_][(k) + 2u] * w2_ + X[r_][(k) + 3u] * w3_; \
      acc[r_][j] += t_.x; acc[r_][(j) + 1u] += t_.y; acc[r_][(j) + 2u] += t_.z; acc[r_][(j) + 3u] += t_.w; \
    }                                                                                            \
  }

// acc[r][j] = bias[n0 + j] + sum_k XA[r][k] W[k][n0 + j] + sum_k XB[r][k] W[KA4 + k][n0 + j] for
// j < BLK (a multiple of 4); KB4 = 0: no second input (XB is not read).
#define DENSE_ACCUMULATE(acc, BLK, n0, XA, KA4, XB, KB4, WOFF4, N4)                              \
  {                                                                                              \
    [[unroll]] for (uint j_ = 0; j_ < (BLK); j_ += 4u) {                                         \
      vec4 b4_ = imageLoad(P, int((WOFF4) + ((KA4) + (KB4)) * (N4) / 4u + ((n0) + j_) / 4u));       \
      [[unroll]] for (uint r_ = 0; r_ < R; r_++) {                                               \
        acc[r_][j_] = b4_.x; acc[r_][j_ + 1u] = b4_.y; acc[r_][j_ + 2u] = b4_.z; acc[r_][j_ + 3u] = b4_.w; \
      }                                                                                          \
    }                                                                                            \
    [[unroll]] for (uint k_ = 0; k_ < (KA4); k_ += 4u)                                           \
      [[unroll]] for (uint j_ = 0; j_ < (BLK); j_ += 4u) DENSE_K4(acc, XA, k_, k_, n0, j_, WOFF4, N4) \
    [[unroll]] for (uint k_ = 0; k_ < (KB4); k_ += 4u)                                           \
      [[unroll]] for (uint j_ = 0; j_ < (BLK); j_ += 4u) DENSE_K4(acc, XB, k_, (KA4) + k_, n0, j_, WOFF4, N4) \
  }

// X[r][0 .. K4) = row min(row0 + r G, count - 1) of the rgba32f texel buffer IMG (stride4 vec4s a
// row): rows past `count` read the last row, so every lane computes and only the stores are masked.
#define DENSE_LOAD_ROWS(X, IMG, K4, stride4, row0, G, count)                                      \
  [[unroll]] for (uint r_ = 0; r_ < R; r_++) DENSE_LOAD_ROW(X, r_, IMG, K4, stride4, min((row0) + r_ * (G), (count) - 1u))

// X[r][0 .. K4) = row `row` of IMG (stride4 vec4s a row).
#define DENSE_LOAD_ROW(X, r, IMG, K4, stride4, row) DENSE_LOAD_ROW_FROM(X, r, IMG, 0u, K4, stride4, row)

// X[r][K0 .. K4) = those columns of row `row` of IMG (K0 a multiple of 4); X's columns before K0 are left.
#define DENSE_LOAD_ROW_FROM(X, r, IMG, K0, K4, stride4, row)                                     \
  [[unroll]] for (uint q_ = (K0) / 4u; q_ < (K4) / 4u; q_++) {                                   \
    vec4 v_ = imageLoad(IMG, int((row) * (stride4) + q_));                                       \
    X[r][4u * q_] = v_.x; X[r][4u * q_ + 1u] = v_.y; X[r][4u * q_ + 2u] = v_.z; X[r][4u * q_ + 3u] = v_.w; \
  }

// Invocation i owns rows i, i + G, ..., i + (R - 1) G of a dispatch of G invocations. Under a device
// row limit (count < the recorded count) only the invocations that `count` rows need run, strided
// by their own number (the dispatch is indirect, sized for the limit, or direct, for the whole batch).
uint denseRowStride(uint count, uint recordedCount) {
  uint G = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  if (count < recordedCount)
    G = min(G, (((count + R - 1u) / R) + gl_WorkGroupSize.x - 1u) / gl_WorkGroupSize.x * gl_WorkGroupSize.x);
  return G;
}

#endif

#version 450
// The NeRF MLP's density alone, from the trunk's last output: sigma is column V of the feature
// layer (its bias plus h . W[:, V]), through the density activation. The occupancy update needs
// nothing else, so the other feature columns, the colour layer and the head are skipped: for the
// fast model that is 4 of the feature layer's V + 4 columns, and no colour work at all. The sums
// are mlp_dense.comp's (dense_block.glsl, the 4-column block that holds sigma), so sigma comes
// out as the full forward computes it.
//
// Layouts: src/core/layouts/mlp_layout.h (NerfShape). Rows past `count` read the last row and store
// nothing.
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "network/mlp_common.glsl"

#include "network/mlp_nerf_density_shared.h"

layout(binding = 0, rgba32f) uniform readonly imageBuffer H;  // the trunk's last output
layout(binding = 1, rgba32f) uniform readonly imageBuffer P;
layout(std430, binding = 2) writeonly buffer Density { float density[]; };
#include "network/dense_block.glsl"  // after R and P
#define ROW_LIMIT_BINDING 3
#include "gpu/row_limit.glsl"

void main() {
  uint row0 = gl_GlobalInvocationID.x;
  uint count = limitedRows(pc.count, pc.limitBase);
  uint G = denseRowStride(count, pc.count);
  if (row0 >= G) return;
  float x[R][K4];
  DENSE_LOAD_ROWS(x, H, K4, pc.strideH4, row0, G, count)
  float acc[R][4];  // sigma, then the feature layer's 3 zero padding columns
  DENSE_ACCUMULATE(acc, 4u, V, x, K4, x, 0u, WOFF4, N4)
  [[unroll]] for (uint r = 0; r < R; r++) {
    uint row = row0 + r * G;
    if (row < count) density[row] = mlpDensity(DENSITY, acc[r][0]);
  }
}

#version 450
// NeRF output head, forward: out = vec4(sigmoid(c H + bias), density(f[W])) per row, where c is the
// colour hidden layer (K4 = W/2 wide), H the [K4][4] head weights at vec4 offset WOFF4 (column 3 is
// padding) and f[W] the sigma pre-activation stored by the feature layer (column SIGMA_COL of F).
// COLOUR = 0: the density alone (NerfRows::densityOnly: a proposal's), out = vec4(0, 0, 0, sigma)
// as the fused density-only forward writes it; C is not read (the colour layer did not run).
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "network/mlp_common.glsl"

#include "network/mlp_nerf_head_shared.h"

layout(binding = 0, rgba32f) uniform readonly imageBuffer C;
layout(binding = 1, rgba32f) uniform readonly imageBuffer F;
layout(binding = 2, rgba32f) uniform readonly imageBuffer P;
layout(std430, binding = 3) writeonly buffer Out { vec4 out4[]; };
#define ROW_GATHER_BINDING 4
#include "gpu/row_gather.glsl"  // with pc.gather, row i of the batch is row rowGather[i] of C, F and Out
#define ROW_LIMIT_BINDING 5
#include "gpu/row_limit.glsl"

void main() {
  uint row = gl_GlobalInvocationID.x;
  uint count = limitedRows(pc.count, pc.limitBase);
  if (count == 0u) return;
  uint rc = gatheredRow(min(row, count - 1u), pc.gather);
  float sigmaPre = imageLoad(F, int(rc * pc.strideF4 + SIGMA_COL / 4u)).x;
  if (COLOUR == 0u) {
    if (row < count) out4[rc * pc.strideOut4] = vec4(0.0, 0.0, 0.0, mlpDensity(DENSITY, sigmaPre));
    return;
  }
  vec4 acc = imageLoad(P, int(WOFF4 + K4));  // bias
  [[unroll]] for (uint q = 0; q < K4 / 4u; q++) {
    vec4 c = imageLoad(C, int(rc * pc.strideC4 + q));
    acc += c.x * imageLoad(P, int(WOFF4 + 4u * q)) + c.y * imageLoad(P, int(WOFF4 + 4u * q + 1u)) +
           c.z * imageLoad(P, int(WOFF4 + 4u * q + 2u)) + c.w * imageLoad(P, int(WOFF4 + 4u * q + 3u));
  }
  if (row < count) out4[rc * pc.strideOut4] = vec4(mlpSigmoid(acc).xyz, mlpDensity(DENSITY, sigmaPre));
}

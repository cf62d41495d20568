#version 450
// NeRF output head, backward. From dL/d(r, g, b, sigma) per row:
//   dZH = (dL/drgb * rgb (1 - rgb), 0)                      (pre-sigmoid; for the head's dW)
//   dF[SIGMA_COL] = (dL/dsigma * density'(f[W]), 0, 0, 0)   (the feature layer's sigma column)
//   dC = (dZH H^T) * [c > 0]                                 (the colour layer's dZ)
// COLOUR = 0, after a density-only forward (NerfRows::densityOnly: a proposal's, trained on its
// density alone): the rgb of dOut is not read and the colour branch has no gradient, so only dF's
// block of 4 from SIGMA_COL is written (the feature layer's backward reads dF from that column on,
// its columns before taken as 0: what the colour layer's input gradient gives for a zero dL/drgb),
// and neither dZH nor dC is written; Out and C are not read.
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "network/mlp_common.glsl"

#include "network/mlp_nerf_head_backward_shared.h"

layout(binding = 0, rgba32f) uniform readonly imageBuffer DOut;
layout(binding = 1, rgba32f) uniform readonly imageBuffer Out;
layout(binding = 2, rgba32f) uniform readonly imageBuffer C;
layout(binding = 3, rgba32f) uniform readonly imageBuffer F;
layout(binding = 4, rgba32f) uniform readonly imageBuffer P;
layout(std430, binding = 5) writeonly buffer DZH { vec4 dzh4[]; };
layout(std430, binding = 6) writeonly buffer DF { vec4 df4[]; };
layout(std430, binding = 7) writeonly buffer DC { vec4 dc4[]; };
#define ROW_GATHER_BINDING 8
#include "gpu/row_gather.glsl"  // the forward's rows (DOut, Out, C, F) at the gathered rows
#define ROW_LIMIT_BINDING 9
#include "gpu/row_limit.glsl"

void main() {
  uint row = gl_GlobalInvocationID.x;
  uint count = limitedRows(pc.count, pc.limitBase);
  if (count == 0u) return;
  uint rc = gatheredRow(min(row, count - 1u), pc.gather);
  vec4 g = imageLoad(DOut, int(rc * pc.strideDOut4));
  float sigmaPre = imageLoad(F, int(rc * pc.strideF4 + SIGMA_COL / 4u)).x;
  float dsigma = g.w * mlpDensityGrad(DENSITY, sigmaPre);
  if (COLOUR == 0u) {
    if (row >= count) return;
    df4[row * pc.strideDF4 + SIGMA_COL / 4u] = vec4(dsigma, 0.0, 0.0, 0.0);
    return;
  }
  vec4 o = imageLoad(Out, int(rc * pc.strideOut4));
  vec4 dzh = vec4(g.xyz * o.xyz * (1.0 - o.xyz), 0.0);
  if (row >= count) return;
  dzh4[row] = dzh;
  df4[row * pc.strideDF4 + SIGMA_COL / 4u] = vec4(dsigma, 0.0, 0.0, 0.0);
  [[unroll]] for (uint q = 0; q < K4 / 4u; q++) {
    vec4 c = imageLoad(C, int(rc * pc.strideC4 + q));
    vec4 d = vec4(dot(dzh, imageLoad(P, int(WOFF4 + 4u * q))), dot(dzh, imageLoad(P, int(WOFF4 + 4u * q + 1u))),
                  dot(dzh, imageLoad(P, int(WOFF4 + 4u * q + 2u))), dot(dzh, imageLoad(P, int(WOFF4 + 4u * q + 3u))));
    dc4[row * pc.strideDC4 + q] = d * vec4(greaterThan(c, vec4(0.0)));
  }
}

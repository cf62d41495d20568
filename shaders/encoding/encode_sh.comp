#version 450
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
// Real spherical harmonics of unit directions up to DEGREE bands (DEGREE^2 <= 16 coefficients),
// instant-ngp's basis; constants and order in tests/reference/encoding/sh_encoding.h. One invocation per row,
// written as whole vec4s into a row-major feature matrix at a 4-aligned column offset, the
// block's last vec4 zero-padded.
layout(local_size_x = 64) in;

#include "encoding/encode_sh_shared.h"
const uint OUT_DIMS = DEGREE * DEGREE;
const uint OUT_VEC4 = (OUT_DIMS + 3u) / 4u;

layout(binding = 0, rgba32f) uniform readonly imageBuffer directions;
layout(std430, binding = 1) writeonly buffer Features { vec4 features[]; };
#define ROW_GATHER_BINDING 2
#include "gpu/row_gather.glsl"  // with pc.gather, invocation i encodes row rowGather[i]
#define ROW_LIMIT_BINDING 3
#include "gpu/row_limit.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= limitedRows(pc.count, pc.limitBase)) return;
  uint row = gatheredRow(i, pc.gather);
  vec3 d = imageLoad(directions, int(row)).xyz;
  float x = d.x, y = d.y, z = d.z;
  float xy = x * y, xz = x * z, yz = y * z, x2 = x * x, y2 = y * y, z2 = z * z;
  float o[16];
  o[0] = 0.28209479177387814;
  o[1] = -0.48860251190291987 * y;
  o[2] = 0.48860251190291987 * z;
  o[3] = -0.48860251190291987 * x;
  o[4] = 1.0925484305920792 * xy;
  o[5] = -1.0925484305920792 * yz;
  o[6] = 0.94617469575755997 * z2 - 0.31539156525251999;
  o[7] = -1.0925484305920792 * xz;
  o[8] = 0.54627421529603959 * x2 - 0.54627421529603959 * y2;
  o[9] = 0.59004358992664352 * y * (-3.0 * x2 + y2);
  o[10] = 2.8906114426405538 * xy * z;
  o[11] = 0.45704579946446572 * y * (1.0 - 5.0 * z2);
  o[12] = 0.3731763325901154 * z * (5.0 * z2 - 3.0);
  o[13] = 0.45704579946446572 * x * (1.0 - 5.0 * z2);
  o[14] = 1.4453057213202769 * z * (x2 - y2);
  o[15] = 0.59004358992664352 * x * (-x2 + 3.0 * y2);
  [[unroll]] for (uint j = OUT_DIMS; j < 16u; ++j) o[j] = 0.0;
  uint dst = row * pc.strideVec4 + pc.offsetVec4;
  [[unroll]] for (uint j = 0u; j < OUT_VEC4; ++j)
    features[dst + j] = vec4(o[4u * j], o[4u * j + 1u], o[4u * j + 2u], o[4u * j + 3u]);
}

#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// Frequency (positional) encoding gamma(p), one invocation per row:
//   [p_0 .. p_{D-1}] if INCLUDE_INPUT, then for k in 0..L-1:
//   [sin(2^k pi p_0) .. sin(2^k pi p_{D-1}), cos(2^k pi p_0) .. cos(2^k pi p_{D-1})]
// written into a row-major feature matrix at a 4-aligned column offset, as whole vec4s (half the
// per-float store cost of scalar stores on lavapipe); the block's last vec4 is zero-padded.
layout(local_size_x = 64) in;

#include "encoding/encode_frequency_shared.h"
const uint OUT_DIMS = DIMS * (2u * LEVELS + INCLUDE_INPUT);
const uint OUT_VEC4 = (OUT_DIMS + 3u) / 4u;

layout(std430, binding = 0) readonly buffer Inputs { vec4 inputs[]; };
layout(std430, binding = 1) writeonly buffer Features { vec4 features[]; };

const float PI = 3.14159265358979;

// sin(pi x), cos(pi x) to a few ulp for any float x. Vulkan only promises 2^-11 absolute error for
// sin/cos on [-pi, pi], and float(2^9 pi x) alone loses ~1e-4, so: reduce exactly to
// f in [-1/4, 1/4] with x = f + q/2 (each step below is exact in float: the differences are
// multiples of the operands' ulp and no larger than them), evaluate Taylor polynomials of
// pi f (truncation < 2e-9 at |pi f| = pi/4), then rotate by the quarter turns q.
void sinCosPi(float x, out float s, out float c) {
  float r = x - 2.0 * round(0.5 * x);  // [-1, 1]
  float q = round(2.0 * r);            // -2..2
  float f = r - 0.5 * q;               // [-1/4, 1/4]
  float a = PI * f;
  float a2 = a * a;
  float sp = a * (1.0 + a2 * (-1.0 / 6.0 + a2 * (1.0 / 120.0 + a2 * (-1.0 / 5040.0 + a2 * (1.0 / 362880.0)))));
  float cp = 1.0 + a2 * (-0.5 + a2 * (1.0 / 24.0 + a2 * (-1.0 / 720.0 + a2 * (1.0 / 40320.0))));
  int quarter = int(q) & 3;            // pi x = pi f + quarter * pi/2 (mod 2 pi)
  s = quarter == 0 ? sp : quarter == 1 ? cp : quarter == 2 ? -sp : -cp;
  c = quarter == 0 ? cp : quarter == 1 ? -sp : quarter == 2 ? -cp : sp;
}

void main() {
  uint row = gl_GlobalInvocationID.x;
  if (row >= pc.count) return;
  vec4 p = inputs[row];
  float v[OUT_VEC4 * 4u];
  [[unroll]] for (uint j = OUT_DIMS; j < OUT_VEC4 * 4u; ++j) v[j] = 0.0;
  const uint base = INCLUDE_INPUT * DIMS;
  [[unroll]] for (uint i = 0u; i < INCLUDE_INPUT * DIMS; ++i) v[i] = p[i];
  [[unroll]] for (uint k = 0u; k < LEVELS; ++k) {
    float scale = float(1u << k);  // exact: scaling by 2^k keeps every bit of p
    [[unroll]] for (uint i = 0u; i < DIMS; ++i) {
      float s, c;
      sinCosPi(scale * p[i], s, c);
      v[base + 2u * DIMS * k + i] = s;
      v[base + 2u * DIMS * k + DIMS + i] = c;
    }
  }
  uint dst = row * pc.strideVec4 + pc.offsetVec4;
  [[unroll]] for (uint j = 0u; j < OUT_VEC4; ++j)
    features[dst + j] = vec4(v[4u * j], v[4u * j + 1u], v[4u * j + 2u], v[4u * j + 3u]);
}

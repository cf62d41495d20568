#version 450
#extension GL_GOOGLE_include_directive : require
// Appearance embedding, forward: the bias a photo's vector adds to the colour layer's
// pre-activation, bias[p] = vectors[first + p] W_a for p < count (W_a: the vector's weights, dims rows
// of the layer's width: what the vector's columns of the layer's input would multiply). Written once
// a step for every training photo, or once a render for its one vector (the mean or a chosen
// photo's); the layer then adds a row's photo's bias (shaders/network/row_bias.glsl) instead of
// reading the vector from every row. One invocation per vec4 of a bias row.
// ref: tests/reference/encoding/appearance.h.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Vectors { float vectors[]; };
layout(std430, binding = 1) readonly buffer Weights { vec4 weights[]; };
layout(std430, binding = 2) writeonly buffer Bias { vec4 bias[]; };

#include "encoding/appearance_bias_shared.h"

void main() {
  uint i = gl_GlobalInvocationID.x, q = i % pc.widthVec4, p = i / pc.widthVec4;
  if (p >= pc.count) return;
  vec4 s = vec4(0.0);
  for (uint k = 0u; k < pc.dims; ++k) s += vectors[(pc.first + p) * pc.dims + k] * weights[k * pc.widthVec4 + q];
  bias[p * pc.widthVec4 + q] = s;
}

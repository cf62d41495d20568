#version 450
#extension GL_GOOGLE_include_directive : require
// Output layer of the plain MLP, backward through its sigmoid: dZ = dY * y (1 - y) per vec4 of
// columns; padding columns (>= NTRUE) get 0 so their weights never move.
layout(local_size_x = 64) in;
#include "common/flat_index.glsl"
#include "network/mlp_sigmoid_backward_shared.h"

layout(binding = 0, rgba32f) uniform readonly imageBuffer DY;
layout(binding = 1, rgba32f) uniform readonly imageBuffer Y;
layout(std430, binding = 2) writeonly buffer DZ { vec4 dz4[]; };

void main() {
  // Flat over x and y (Recorder::dispatchFlat): a vec4 of columns a lane, past 65,535 groups.
  uint i = flatIndex(64u), row = i / (N4 / 4u), q = i % (N4 / 4u);
  if (row >= pc.count) return;
  vec4 y = imageLoad(Y, int(row * pc.strideY4 + q));
  vec4 d = imageLoad(DY, int(row * pc.strideDY4 + q)) * y * (1.0 - y);
  dz4[row * pc.strideDZ4 + q] = mix(vec4(0.0), d, lessThan(uvec4(4u * q) + uvec4(0, 1, 2, 3), uvec4(NTRUE)));
}

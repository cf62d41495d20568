#version 450
#extension GL_GOOGLE_include_directive : require
// Appearance embedding, backward: the gradient of the vectors' weights W_a, dW_a[k] = sum over the
// photos c of vectors[c][k] g_c (g_c: photo c's sum of dL/d(colour pre-activation), from
// appearance_gradient.comp). One invocation per vec4 of W_a, summing the photos in order
// (deterministic). Writes (does not add to) the gradient. ref: tests/reference/encoding/appearance.h.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Vectors { float vectors[]; };   // dims a photo
layout(std430, binding = 1) readonly buffer PhotoSums { vec4 photoSums[]; };  // widthVec4 a photo
layout(std430, binding = 2) writeonly buffer Grads { vec4 grads[]; };        // dims rows of widthVec4

#include "encoding/appearance_weights_gradient_shared.h"

void main() {
  uint i = gl_GlobalInvocationID.x, q = i % pc.widthVec4, k = i / pc.widthVec4;
  if (k >= pc.dims) return;
  vec4 s = vec4(0.0);
  for (uint c = 0u; c < pc.numCameras; ++c) s += vectors[c * pc.dims + k] * photoSums[c * pc.widthVec4 + q];
  grads[k * pc.widthVec4 + q] = s;
}

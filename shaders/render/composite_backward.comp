#version 450
// Volume-rendering compositing, backward, O(N) per ray in two passes over its samples.
//   dC/dsigma_i = delta_i * (T_{i+1} c_i - R_i),  R_i = sum_{j>i} w_j c_j + T_final * bg
// (depth likewise with t_i and no background; opacity: delta_i * T_final), dC/dc_i = w_i.
// R_i is never formed as "total minus prefix", which cancels to noise once T is small. Instead the
// back-to-front pass carries Q_i = R_i / T_{i+1} = alpha_{i+1} c_{i+1} + exp(-x_{i+1}) Q_{i+1},
// Q_N = bg: a convex mix of colours, so it stays O(1) and exact-ish however deep the ray goes, and
// dC/dsigma_i = delta_i * T_{i+1} * (c_i - Q_i) is exactly 0 (never NaN) where T_{i+1} underflows.
// The front-to-back pass stores T_{i+1} per sample in dField, whose slots this invocation owns; the
// back-to-front pass reads them and overwrites them with the gradients.
// With early termination (composite.glsl) the ray ends where the forward pass stopped it: the
// samples behind the cut get a zero gradient, the rest exactly what a batch holding only the kept
// samples would get.
#extension GL_GOOGLE_include_directive : require
#include "render/composite.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer RayOffsets { uint rayOffsets[]; };
layout(std430, binding = 1) readonly buffer Samples { vec2 samples[]; };  // (t, delta)
layout(binding = 2, rgba32f) uniform readonly imageBuffer field;         // (r, g, b, sigma)
layout(std430, binding = 3) readonly buffer Background { vec4 perRayBackground[]; };
layout(std430, binding = 4) readonly buffer DColor { vec4 dColor[]; };   // dL/d(r, g, b, opacity)
layout(std430, binding = 5) readonly buffer DDepth { float dDepth[]; };
layout(std430, binding = 6) buffer DField { vec4 dField[]; };            // dL/d(r, g, b, sigma)

layout(push_constant) uniform Push {
  vec4 background;
  uint numRays;
  uint samplesPerRay;
  uint useBackgroundBuffer;
  float maxOpticalDepth;
  uint writeKept;  // the forward pass's; unused here
} pc;

void main() {
  uint ray = gl_GlobalInvocationID.x;
  if (ray >= pc.numRays) return;
  uint begin = pc.samplesPerRay > 0u ? ray * pc.samplesPerRay : rayOffsets[ray];
  uint end = pc.samplesPerRay > 0u ? begin + pc.samplesPerRay : rayOffsets[ray + 1u];

  // Front to back: the same prefix sums as the forward pass, so T matches it bit for bit. Only
  // T_{i+1} is kept (in dField[i].x); alpha is cheaper to recompute than to store and reload.
  float prefix = 0.0;
  float opaque = 0.0;
  uint cut = begin;
  for (; cut < end && opaque <= pc.maxOpticalDepth; ++cut) {
    float sigma = imageLoad(field, int(cut)).w, delta = samples[cut].y;
    prefix += opticalDepth(sigma, delta);
    dField[cut].x = exp(-prefix);
    opaque += terminationDepth(sigma, delta);
  }
  for (uint i = cut; i < end; ++i) dField[i] = vec4(0.0);
  end = cut;

  vec4 g = dColor[ray];
  float gDepth = dDepth[ray];
  float opacityTerm = g.w * exp(-prefix);  // dO/dsigma_i = delta_i * T_final
  vec3 q = pc.useBackgroundBuffer != 0u ? perRayBackground[ray].rgb : pc.background.rgb;
  float qDepth = 0.0;
  float tOut = exp(-prefix);
  for (uint i = end; i > begin;) {
    --i;
    float tIn = i > begin ? dField[i - 1u].x : 1.0;
    vec2 s = samples[i];
    vec4 f = imageLoad(field, int(i));
    vec2 a = alphaAndSurvival(opticalDepth(f.w, s.y));
    float inner = tOut * (dot(g.rgb, f.rgb - q) + gDepth * (s.x - qDepth)) + opacityTerm;
    // delta_i = 0 multiplies a finite inner: the gradient of a duplicate sample is exactly 0.
    dField[i] = vec4(tIn * a.x * g.rgb, s.y * inner);
    q = a.x * f.rgb + a.y * q;
    qDepth = a.x * s.x + a.y * qDepth;
    tOut = tIn;
  }
}

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
//
// Distortion loss (mip-NeRF 360; pc.distortion > 0 is its weight per ray): L = sum_{i,j} w_i w_j
// |m_i - m_j| + 1/3 sum_i w_i^2 l_i penalises weight spread along the ray (fog, floaters), with
// dL/dw_i = 2 (m_i W_i - S_i + S'_i - m_i W'_i) + 2/3 w_i l_i, where W, S are the sums of w and w m
// over the samples in front of i and W', S' behind it: O(n), the front-to-back pass keeps W_i and
// S_i in dField[i].yz, the back-to-front pass carries W' and S'. It reaches sigma_k as
// delta_k (g_k T_{k+1} - D_k), D_k = sum_{i>k} g_i w_i, also carried back to front. m and l are
// taken in the ray's normalised distance s in [0, 1], even in march steps (render/distortion.glsl,
// tests/reference/render/distortion_loss.h): the loss is the same in any units and wherever the ray
// starts, so one weight serves every scene. With pc.distortionFarField the far field's weight
// T_final counts as one more interval, at s = 1 and of length 0 (ref::DistortionRay::farField).
// With pc.writeTermValues, each ray's value of the loss terms it adds, weighted, goes to
// termValues[ray] (x: the distortion loss, 2 sum_i w_i (m_i W_i - S_i) + 1/3 sum_i w_i^2 l_i, the
// pairwise sum taken once per pair from the front pass's running sums) for the loss's report.
#extension GL_GOOGLE_include_directive : require
#include "render/composite.glsl"
#include "render/distortion.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer RayOffsets { uint rayOffsets[]; };
layout(std430, binding = 1) readonly buffer Samples { vec2 samples[]; };  // (t, delta)
layout(binding = 2, rgba32f) uniform readonly imageBuffer field;         // (r, g, b, sigma)
layout(std430, binding = 3) readonly buffer Background { vec4 perRayBackground[]; };
layout(std430, binding = 4) readonly buffer DColor { vec4 dColor[]; };   // dL/d(r, g, b, opacity)
layout(std430, binding = 5) readonly buffer DDepth { float dDepth[]; };
layout(std430, binding = 6) buffer DField { vec4 dField[]; };            // dL/d(r, g, b, sigma)
// binding 7: the forward pass's kept counts, unbound here
layout(std430, binding = 8) readonly buffer Rays { vec4 rays[]; };       // (o, t_near), (d, t_far): the distortion loss's
layout(std430, binding = 9) writeonly buffer TermValues { vec4 termValues[]; };  // per ray: x distortion

#include "render/composite_shared.h"

void main() {
  uint ray = gl_GlobalInvocationID.x;
  if (ray >= pc.numRays) return;
  uint begin = pc.samplesPerRay > 0u ? ray * pc.samplesPerRay : rayOffsets[ray];
  uint end = pc.samplesPerRay > 0u ? begin + pc.samplesPerRay : rayOffsets[ray + 1u];

  // Front to back: the same prefix sums as the forward pass, so T matches it bit for bit. Only
  // T_{i+1} is kept (in dField[i].x); alpha is cheaper to recompute than to store and reload.
  // With the distortion loss, also W_i and S_i (dField[i].yz) from the forward pass's weights.
  bool distortion = pc.distortion > 0.0;
  MarchSpacing spacing = MarchSpacing(pc.coneAngle, pc.dtMin, pc.dtMax);
  vec2 frame = distortion ? distortionFrame(rays[2u * ray].w, rays[2u * ray + 1u].w, spacing) : vec2(0.0);
  float prefix = 0.0;
  float opaque = 0.0;
  float wFront = 0.0, sFront = 0.0, distortionValue = 0.0;
  bool far = distortion && pc.distortionFarField != 0u;
  float farA = 0.0;  // sum_i w_i |1 - m_i|, with the far field in the loss
  uint cut = begin;
  for (; cut < end && opaque <= pc.maxOpticalDepth; ++cut) {
    float sigma = imageLoad(field, int(cut)).w;
    vec2 s = samples[cut];
    float x = opticalDepth(sigma, s.y);
    if (distortion) {
      float w = exp(-prefix) * alphaAndSurvival(x).x;
      vec2 ml = distortionInterval(s, frame, spacing);
      dField[cut].yz = vec2(wFront, sFront);
      distortionValue += w * (2.0 * (ml.x * wFront - sFront) + (1.0 / 3.0) * w * ml.y);
      wFront += w;
      sFront += w * ml.x;
      farA += w * abs(1.0 - ml.x);
    }
    prefix += x;
    dField[cut].x = exp(-prefix);
    opaque += terminationDepth(sigma, s.y);
  }
  for (uint i = cut; i < end; ++i) dField[i] = vec4(0.0);
  end = cut;
  // The far field in the loss: L += 2 T_final A, A = sum_i w_i |1 - m_i|, so dL/dw_i gains
  // 2 T_final |1 - m_i| and every sigma_k gains -delta_k T_final 2 A (through T_final).
  float tFinal = exp(-prefix);
  if (far) distortionValue += 2.0 * tFinal * farA;
  float farTerm = far ? pc.distortion * 2.0 * farA * tFinal : 0.0;
  if (pc.writeTermValues != 0u) termValues[ray] = vec4(pc.distortion * distortionValue, 0.0, 0.0, 0.0);

  vec4 g = dColor[ray];
  float gDepth = dDepth[ray];
  float opacityTerm = g.w * exp(-prefix);  // dO/dsigma_i = delta_i * T_final
  vec3 q = pc.useBackgroundBuffer != 0u ? perRayBackground[ray].rgb : pc.background.rgb;
  float qDepth = 0.0;
  float tOut = exp(-prefix);
  float wBehind = 0.0, sBehind = 0.0, dBehind = 0.0;  // W', S' and D of the distortion loss
  for (uint i = end; i > begin;) {
    --i;
    float tIn = i > begin ? dField[i - 1u].x : 1.0;
    vec2 s = samples[i];
    vec4 f = imageLoad(field, int(i));
    vec2 a = alphaAndSurvival(opticalDepth(f.w, s.y));
    float inner = tOut * (dot(g.rgb, f.rgb - q) + gDepth * (s.x - qDepth)) + opacityTerm;
    if (distortion) {
      vec2 front = dField[i].yz, ml = distortionInterval(s, frame, spacing);
      float w = tIn * a.x;
      float gw = pc.distortion * (2.0 * (ml.x * front.x - front.y + sBehind - ml.x * wBehind) + (2.0 / 3.0) * w * ml.y +
                                  (far ? 2.0 * tFinal * abs(1.0 - ml.x) : 0.0));
      inner += gw * tOut - dBehind - farTerm;
      dBehind += gw * w;
      wBehind += w;
      sBehind += w * ml.x;
    }
    // delta_i = 0 multiplies a finite inner: the gradient of a duplicate sample is exactly 0.
    dField[i] = vec4(tIn * a.x * g.rgb, s.y * inner);
    q = a.x * f.rgb + a.y * q;
    qDepth = a.x * s.x + a.y * qDepth;
    tOut = tIn;
  }
}

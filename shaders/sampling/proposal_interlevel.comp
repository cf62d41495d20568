#version 450
// The proposal estimator's interlevel loss (mip-NeRF 360, eq. 13; tests/reference/sampling/proposal.h:
// interlevelLoss): the field's weights w_j on a ray's samples against the proposal's weights on its
// candidates, both as bins in occupied length. B_j, the proposal weight of every candidate that
// overlaps sample j's bin by a positive length, should bound w_j:
//   L = weight * sum_j max(0, w_j - B_j)^2 / (w_j + epsilon).
// The field's weights are constants here (nerfacto stops their gradient): only the proposal learns.
// One invocation per ray, three walks, no per-ray arrays:
//   1. candidates front to back: dWeights = 0, and dField.w holds each candidate's inclusive optical
//      depth for walk 3 (a back-to-front walk cannot recover it without cancellation);
//   2. samples front to back with a window of the candidates that overlap each: B_j, the loss, and
//      dL/dB_j added to dWeights over the window (consecutive windows share at most one candidate,
//      so the walk is O(candidates + samples));
//   3. candidates back to front: dL/dsigma_k = delta_k T_k+1 (g_k - Q_k), Q the weights'
//      gradients behind k seen from k (as composite_backward.comp carries its suffix sums).
#extension GL_GOOGLE_include_directive : require
#include "sampling/sampling.glsl"

layout(std430, binding = 0) readonly buffer CandidateOffsets { uint candidateOffsets[]; };  // numRays + 1
layout(std430, binding = 1) readonly buffer Candidates { vec2 candidates[]; };              // (t, delta)
layout(std430, binding = 2) readonly buffer ProposalField { vec4 proposalField[]; };       // sigma in w
layout(std430, binding = 3) readonly buffer SampleOffsets { uint sampleOffsets[]; };        // numRays + 1
layout(std430, binding = 4) readonly buffer Samples { vec2 samples[]; };                    // (t, delta)
layout(std430, binding = 5) readonly buffer FieldWeights { float fieldWeights[]; };         // per sample
layout(std430, binding = 6) buffer DWeights { float dWeights[]; };                          // per candidate
layout(std430, binding = 7) buffer DField { vec4 dField[]; };                               // (0, 0, 0, dL/dsigma)
layout(std430, binding = 8) writeonly buffer RayLoss { float rayLoss[]; };                  // per ray

#include "sampling/proposal_interlevel_shared.h"
#include "sampling/proposal.glsl"

// A field weight is in [0, 1]; anything else (NaN included) is clamped into it.
float fieldWeight(uint j) {
  float w = fieldWeights[j];
  return w >= 0.0 ? min(w, 1.0) : 0.0;
}

bool overlapsPositively(float a0, float a1, float b0, float b1) { return min(a1, b1) > max(a0, b0); }

void main() {
  uint ray = flatInvocation();
  if (ray >= pc.numRays) return;
  uint c0 = candidateOffsets[ray], c1 = candidateOffsets[ray + 1u];
  uint s0 = sampleOffsets[ray], s1 = sampleOffsets[ray + 1u];

  for (CandidateWalk w = beginWalk(c0); w.index < c1;) {
    uint i = w.index;
    advance(w);
    dWeights[i] = 0.0;
    dField[i] = vec4(0.0, 0.0, 0.0, w.prefix);
  }

  precise float loss = 0.0;
  CandidateWalk window = beginWalk(c0);  // the first candidate that ends after the current bin's start
  float e0 = 0.0;
  for (uint j = s0; j < s1; ++j) {
    precise float e1 = e0 + max(samples[j].y, 0.0);
    while (window.index < c1 && window.start + candidateLength(window.index) <= e0) advance(window);
    precise float bound = 0.0;
    for (CandidateWalk w = window; w.index < c1 && w.start < e1; advance(w))
      if (overlapsPositively(w.start, w.start + candidateLength(w.index), e0, e1)) bound += walkWeight(w);
    float fw = fieldWeight(j);
    float excess = max(fw - bound, 0.0);
    precise float term = excess * excess / (fw + pc.epsilon);
    loss += term;
    precise float dBound = -2.0 * pc.weight * excess / (fw + pc.epsilon);
    if (dBound != 0.0)
      for (CandidateWalk w = window; w.index < c1 && w.start < e1; advance(w))
        if (overlapsPositively(w.start, w.start + candidateLength(w.index), e0, e1)) dWeights[w.index] += dBound;
    e0 = e1;
  }
  rayLoss[ray] = pc.weight * loss;

  float q = 0.0;
  for (uint i = c1; i-- > c0;) {
    float delta = candidates[i].y;
    float g = dWeights[i];
    float alpha = alphaAndSurvival(candidateDepth(i)).x;
    precise float d = delta > 0.0 ? delta * exp(-dField[i].w) * (g - q) : 0.0;
    dField[i] = vec4(0.0, 0.0, 0.0, d);
    precise float nextQ = g * alpha + (1.0 - alpha) * q;
    q = nextQ;
  }
}

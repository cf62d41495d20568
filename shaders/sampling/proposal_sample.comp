#version 450
// The proposal estimator's sampling (nerfacto's proposal sampler; tests/reference/sampling/proposal.h:
// proposalSamples): a ray's candidates (the march's samples) and the proposal's density at each
// give weights w_i = T_i alpha_i; the ray's samples are the bins between the inverse-CDF edges of
// those weights (plus a uniform padding), measured in occupied length so that the march's skipped
// gaps cost nothing, each evaluated at its midpoint with delta = its length. One invocation per
// ray walks its candidates three times (the length, the mass, then the edges with a second pointer mapping each
// midpoint back to t): O(candidates + samples), whatever the weights. With pc.points it also writes
// each sample's field inputs, as march_points.comp would from them (one pass less over the batch).
#extension GL_GOOGLE_include_directive : require
#include "sampling/sampling.glsl"

layout(std430, binding = 0) readonly buffer CandidateOffsets { uint candidateOffsets[]; };  // numRays + 1
layout(std430, binding = 1) readonly buffer Candidates { vec2 candidates[]; };              // (t, delta)
layout(std430, binding = 2) readonly buffer ProposalField { vec4 proposalField[]; };       // sigma in w
layout(std430, binding = 3) readonly buffer SampleOffsets { uint sampleOffsets[]; };        // numRays + 1
layout(std430, binding = 4) writeonly buffer Samples { vec2 samples[]; };                   // (t, delta)
layout(std430, binding = 5) writeonly buffer SampleRay { uint sampleRay[]; };               // per sample
layout(std430, binding = 6) readonly buffer Rays { vec4 rays[]; };                          // (o, t_near), (d, t_far)
layout(std430, binding = 7) writeonly buffer Positions { vec4 positions[]; };               // per sample, with points
layout(std430, binding = 8) writeonly buffer Directions { vec4 directions[]; };

#include "sampling/proposal_sample_shared.h"
#include "sampling/proposal.glsl"
#include "sampling/box_position.glsl"

uint candidateEnd;
float occupiedLength;
bool uniformMass;  // the weights carry no usable distribution: each candidate's mass is its length

// Sample s at t of `ray`, and with pc.points its field inputs (march_points.comp's, bit for bit).
void store(uint s, vec2 sample_, uint ray) {
  samples[s] = sample_;
  sampleRay[s] = ray;
  if (pc.points == 0u) return;
  vec3 o = rays[2u * ray].xyz, d = rays[2u * ray + 1u].xyz;
  precise float t = sample_.x;
  positions[s] = boxPosition(o + t * d, pc.boxMin.xyz, pc.boxMax.xyz);
  directions[s] = vec4(d, 0.0);
}

float massOf(CandidateWalk w) {
  float len = candidateLength(w.index);
  if (uniformMass) return len;
  float weight = walkWeight(w), share = len / occupiedLength;
  weight = weight > 0.0 ? weight : 0.0;
  // Annealed in training's first steps: from uniform by length (a = 0) to the weights (a = 1).
  if (pc.anneal < 1.0 && weight > 0.0) weight = pow(weight, pc.anneal) * pow(share, 1.0 - pc.anneal);
  precise float m = weight + pc.padding * share;
  return m;
}

void main() {
  uint ray = flatInvocation();
  if (ray >= pc.numRays) return;
  uint c0 = candidateOffsets[ray];
  candidateEnd = candidateOffsets[ray + 1u];
  uint s0 = sampleOffsets[ray], n = sampleOffsets[ray + 1u] - s0;
  if (n == 0u) return;

  precise float occupied = 0.0;
  for (uint i = c0; i < candidateEnd; ++i) occupied += candidateLength(i);
  occupiedLength = occupied;
  if (!(occupied > 0.0)) {
    for (uint j = 0u; j < n; ++j) store(s0 + j, vec2(0.0), ray);
    return;
  }
  uniformMass = false;
  precise float total = 0.0;
  for (CandidateWalk w = beginWalk(c0); w.index < candidateEnd; advance(w)) total += massOf(w);
  if (!(total >= kMinMass && total <= kMaxFloat)) {
    uniformMass = true;
    total = occupied;
  }

  float shift = pc.jitter != 0u ? rng01(pc.seed, ray, 0u) - 0.5 : 0.0;
  CandidateWalk edge = beginWalk(c0);  // the candidate the next edge falls in
  float below = 0.0;                   // the mass in front of it
  float mass = massOf(edge);
  uint c = c0;                         // the candidate the next midpoint falls in
  float cStart = 0.0;
  float prevEdge = 0.0;
  for (uint j = 0u; j < n; ++j) {
    float nextEdge = occupied;
    if (j + 1u < n) {
      precise float target = (float(j + 1u) + shift) / float(n) * total;
      while (edge.index + 1u < candidateEnd && below + mass < target) {
        precise float b = below + mass;
        below = b;
        advance(edge);
        mass = massOf(edge);
      }
      precise float frac = (target - below) / max(mass, kMinMass);
      precise float e = edge.start + clamp(frac, 0.0, 1.0) * candidateLength(edge.index);
      nextEdge = clamp(e, prevEdge, occupied);
    }
    precise float mid = (prevEdge + nextEdge) * 0.5;
    while (c + 1u < candidateEnd && cStart + candidateLength(c) <= mid) {
      precise float s = cStart + candidateLength(c);
      cStart = s;
      ++c;
    }
    precise float t = candidates[c].x + clamp(mid - cStart, 0.0, candidateLength(c));
    store(s0 + j, vec2(t, nextEdge - prevEdge), ray);
    prevEdge = nextEdge;
  }
}

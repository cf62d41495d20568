// Shared by proposal_sample.comp and proposal_interlevel.comp: a ray's candidates in occupied
// length, and the proposal's weights on them, computed front to back as a walk advances (no
// per-ray arrays, so no bound on a ray's candidates). The CPU twin is tests/reference/sampling/proposal.h.
//
// Before including, declare the candidates `vec2 candidates[]` (t, delta) and the proposal field
// at them `vec4 proposalField[]` (the density, activated, in w, as a field's (r, g, b, sigma); NaN
// counts as 0 and inf as the largest float, as the occupancy grid reads densities).
#ifndef VKNERF_SAMPLING_PROPOSAL_GLSL
#define VKNERF_SAMPLING_PROPOSAL_GLSL

#include "render/composite.glsl"

// Candidate i's length in occupied length (a negative delta counts as none).
float candidateLength(uint i) { return max(candidates[i].y, 0.0); }

// Candidate i's optical depth under the proposal's density.
float candidateDepth(uint i) { return opticalDepth(sanitizeDensity(proposalField[i].w), candidates[i].y); }

// A walk over a ray's candidates front to back: candidate `index` starts at `start` in occupied
// length and has `prefix` optical depth in front of it.
struct CandidateWalk {
  uint index;
  float start;
  float prefix;
};

CandidateWalk beginWalk(uint first) { return CandidateWalk(first, 0.0, 0.0); }

// The proposal weight T_i alpha_i of the walk's candidate.
float walkWeight(CandidateWalk w) { return exp(-w.prefix) * alphaAndSurvival(candidateDepth(w.index)).x; }

void advance(inout CandidateWalk w) {
  precise float start = w.start + candidateLength(w.index);
  precise float prefix = w.prefix + candidateDepth(w.index);
  w.start = start;
  w.prefix = prefix;
  ++w.index;
}

#endif

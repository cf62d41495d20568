// Shared by composite_forward.comp and composite_backward.comp: which samples a ray owns, and the
// per-sample opacity. The CPU twin is tests/reference/render/composite.h.
//
// Layouts: samples are vec2(t, delta); the field is vec4(r, g, b, sigma) with sigma activated.
// A ray owns samples [r*N, (r+1)*N) when samplesPerRay = N > 0, else [off[r], off[r+1]).
#ifndef VKNERF_COMPOSITE_GLSL
#define VKNERF_COMPOSITE_GLSL

#include "occupancy/occupancy.glsl"

// Optical depth is capped so that sigma = +inf or FLT_MAX never enters the arithmetic as inf:
// exp(-cap) is 0 and 1 - exp(-cap) is 1 exactly, and prefix sums of capped values stay finite
// (no inf - inf or 0 * inf anywhere downstream).
const float kMaxOpticalDepth = 1e30;

// x = sigma * delta, and exactly 0 when delta = 0 (a duplicate sample) even if sigma is inf.
float opticalDepth(float sigma, float delta) { return delta > 0.0 ? min(sigma * delta, kMaxOpticalDepth) : 0.0; }

// alpha = 1 - exp(-x) and its complement exp(-x). Below 0.5 the subtraction would cancel, so alpha
// is the Taylor series in Horner form; the first omitted term, x^10/10!, is 5e-10 of alpha at
// x = 0.5. Above 0.5, alpha >= 0.39 and 1 - exp(-x) loses at most a couple of ulps.
vec2 alphaAndSurvival(float x) {
  float p = 1.0 - x * (1.0 / 9.0);
  p = 1.0 - x * (1.0 / 8.0) * p;
  p = 1.0 - x * (1.0 / 7.0) * p;
  p = 1.0 - x * (1.0 / 6.0) * p;
  p = 1.0 - x * (1.0 / 5.0) * p;
  p = 1.0 - x * (1.0 / 4.0) * p;
  p = 1.0 - x * (1.0 / 3.0) * p;
  p = 1.0 - x * (1.0 / 2.0) * p;
  float series = x * p;
  float e = exp(-x);
  return x < 0.5 ? vec2(series, 1.0 - series) : vec2(1.0 - e, e);
}

// Early termination: a ray stops compositing once the transmittance in front of its next sample
// falls below a threshold, tested as optical depth > maxOpticalDepth = -ln(threshold) so that no
// exp() rounding decides; the sample that crosses it is still composited. The depth is its own
// sum (sanitized density times delta, as the occupancy grid reads densities), so the decision is
// independent of the compositing arithmetic and matches tests/reference's keptSamples bit for bit.
// maxOpticalDepth = +inf never stops.
float terminationDepth(float sigma, float delta) {
  precise float tau = sanitizeDensity(sigma) * delta;
  return tau;
}

#endif

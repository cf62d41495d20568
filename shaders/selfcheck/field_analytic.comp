#version 450
// An analytic radiance field standing in for the MLP in self-checks and tests: a dense sphere and a
// box-shaped fog, colour varying with position. Density ramps over a thin shell so it is continuous
// (float and double pipelines then agree to rounding, not to which side of a jump a sample fell).
#extension GL_GOOGLE_include_directive : require
#include "selfcheck/field_analytic.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Positions { vec4 positions[]; };  // in [-1, 1]^3
layout(std430, binding = 1) writeonly buffer Field { vec4 field[]; };        // (r, g, b, sigma)

layout(push_constant) uniform Push { uint count; } pc;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  field[i] = analyticField(positions[i].xyz);
}

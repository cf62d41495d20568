#version 450
// Background colour per ray: random (a fresh colour per ray and step teaches the field that empty
// space is transparent rather than the colour of one fixed background) or one constant colour.
#extension GL_GOOGLE_include_directive : require
#include "common/rng.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) writeonly buffer Background { vec4 background[]; };

#include "loss/random_background_shared.h"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  background[i] = pc.random != 0u
      ? vec4(rng01(pc.seed, i, 100u), rng01(pc.seed, i, 101u), rng01(pc.seed, i, 102u), 1.0)
      : pc.constant;
}

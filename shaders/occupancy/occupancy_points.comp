#version 450
// Occupancy update, step 1: one jittered point per chosen cell, for the caller to evaluate the
// density field at. Point j goes to cell j (every cell) or to cell rngUint(seed, j, 3) % (cascades R^3) (a
// random subset, as instant-ngp does after warm-up), at offsets rng01(seed, j, axis) inside it.
// Positions are in the normalised box [-1, 1]^3 the field expects, w = 0.
#extension GL_GOOGLE_include_directive : require
#include "occupancy/occupancy.glsl"

layout(local_size_x = 256) in;

layout(std430, binding = 0) writeonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 1) writeonly buffer Cells { uint cells[]; };

#include "occupancy/occupancy_points_shared.h"

void main() {
  uint j = flatIndex(256u);
  if (j >= pc.count) return;
  uint r = pc.resolution;
  uint perCascade = r * r * r;
  uint cell = pc.randomCells != 0u ? rngUint(pc.seed, j, 3u) % (perCascade * pc.cascades) : j;
  uint local = cell % perCascade;
  uvec3 c = uvec3(local % r, (local / r) % r, local / (r * r));
  vec3 u = vec3(rng01(pc.seed, j, 0u), rng01(pc.seed, j, 1u), rng01(pc.seed, j, 2u));
  float scale = 1.0 / float(1u << (pc.cascades - 1u - cell / perCascade));  // 2^(cascade - cascades + 1), exact
  precise vec3 p = ((vec3(c) + u) * (2.0 / float(r)) - 1.0) * scale;
  positions[j] = vec4(p, 0.0);
  cells[j] = cell;
}

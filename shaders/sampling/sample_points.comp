#version 450
#extension GL_GOOGLE_include_directive : require
// Sample positions and directions for the field: one invocation per sample of a fixed-layout batch
// (ray r owns samples [r*N, (r+1)*N)). The position o + t d is mapped from the scene box onto
// [-1, 1]^3, the range the encodings expect; the direction is the ray's unit direction as is.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };        // (o, t_near), (d, t_far)
layout(std430, binding = 1) readonly buffer Samples { vec2 samples[]; };  // (t, delta)
layout(std430, binding = 2) writeonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 3) writeonly buffer Directions { vec4 directions[]; };

#include "sampling/sample_points_shared.h"
#include "sampling/box_position.glsl"
#include "common/flat_index.glsl"

void main() {
  uint s = flatIndex(64u);  // Recorder::dispatchFlat: a batch past 65,535 groups along x
  if (s >= pc.count) return;
  uint r = s / pc.samplesPerRay;
  vec3 o = rays[2 * r].xyz;
  vec3 d = rays[2 * r + 1].xyz;
  positions[s] = boxPosition(o + samples[s].x * d, pc.boxMin.xyz, pc.boxMax.xyz);
  directions[s] = vec4(d, 0.0);
}

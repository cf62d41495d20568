#version 450
// Field inputs of a packed batch: sample s of ray sampleRay[s] becomes the position o + t d (or its
// interval's middle, o + (t + delta / 2) d: nerf::PackedSamplePoints's midpoints) mapped
// from the scene box onto [-1, 1]^3 and the ray's unit direction, both vec4 with w = 0 (the
// packed twin of sample_points.comp). The sample count is the marcher's total (the first uint of
// its totals, bound as the row limit): the dispatches are indirect, chunk by chunk, with workgroup
// counts written on the device (src/gpu/dispatch/limited_dispatch.h), so a batch recorded for its capacity
// launches only the workgroups its samples need.
#extension GL_GOOGLE_include_directive : require
#define ROW_LIMIT_BINDING 5
#include "gpu/row_limit.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Rays { vec4 rays[]; };        // (o, t_near), (d, t_far)
layout(std430, binding = 1) readonly buffer Samples { vec2 samples[]; };  // (t, delta)
layout(std430, binding = 2) readonly buffer SampleRay { uint sampleRay[]; };
layout(std430, binding = 3) writeonly buffer Positions { vec4 positions[]; };
layout(std430, binding = 4) writeonly buffer Directions { vec4 directions[]; };

#include "sampling/march_points_shared.h"
#include "sampling/box_position.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= limitedRows(pc.chunkRows, pc.limitBase)) return;
  uint s = pc.limitBase + i;
  uint r = sampleRay[s];
  vec3 o = rays[2u * r].xyz, d = rays[2u * r + 1u].xyz;
  vec2 ts = samples[s];
  precise float t = pc.midpoints != 0u ? ts.x + 0.5 * ts.y : ts.x;
  positions[s] = boxPosition(o + t * d, pc.boxMin.xyz, pc.boxMax.xyz);
  directions[s] = vec4(d, 0.0);
}

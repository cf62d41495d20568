#version 450
// Partial sums of `count` values, one per workgroup of 128 (value i is values[i * stride +
// component]), reduced in shared memory as loss_photometric.comp's are: no float atomics. The host
// adds the partials in double (a loss term's value for the report, nerf/loss/partial_sums.h).
#extension GL_GOOGLE_include_directive : require

layout(local_size_x = 128) in;

layout(std430, binding = 0) readonly buffer Values { float values[]; };
layout(std430, binding = 1) writeonly buffer Partials { float partials[]; };  // one per workgroup

#include "loss/sum_partials_shared.h"

shared float sums[128];

void main() {
  uint i = gl_GlobalInvocationID.x, l = gl_LocalInvocationID.x;
  sums[l] = i < pc.count ? values[i * pc.stride + pc.component] : 0.0;
  barrier();
  for (uint s = gl_WorkGroupSize.x / 2u; s > 0u; s >>= 1u) {
    if (l < s) sums[l] += sums[l + s];
    barrier();
  }
  if (l == 0u) partials[gl_WorkGroupID.x] = sums[0];
}

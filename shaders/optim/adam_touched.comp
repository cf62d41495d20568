#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// Adam over the sparse part of a table, pass 1: appends to `touched` the index of every vec4 of
// parameters in [first4, first4 + count4) whose gradient is not all zero (what the step touched),
// and counts them in touchedCount (zeroed before). adam_sparse.comp then steps the listed vec4s
// alone. A skip inside one kernel over the whole table saves nothing on lavapipe: a hash level's
// touched entries are scattered, so nearly every 8-lane slice holds one and runs the whole update
// under a mask; the list packs them. Each invocation lists its 16 vec4s in order at an offset it
// takes with one atomic; the invocations' order varies, the list's content does not. (A workgroup
// once summed its invocations' counts to take one offset for all: the scan's barriers, each a
// coroutine switch on lavapipe, took the pass over the sample scene's 2^19 table from 4.6 to 6.7 ms.)
layout(local_size_x = 64) in;

layout(binding = 0, rgba32f) uniform readonly imageBuffer G4;
layout(std430, binding = 1) writeonly buffer Touched { uint touched[]; };
layout(std430, binding = 2) buffer TouchedCount { uint touchedCount; };

#include "optim/adam_touched_shared.h"

const uint kInvocations = 64u, kPerInvocation = 16u;

void main() {
  uint lid = gl_LocalInvocationID.x;
  uint base = gl_WorkGroupID.x * kInvocations * kPerInvocation + lid * kPerInvocation;
  uint live = 0u, n = 0u;
  [[unroll]] for (uint j = 0u; j < kPerInvocation; ++j) {
    uint i = base + j;
    bool t = i < pc.count4 && any(notEqual(imageLoad(G4, int(pc.first4 + i)), vec4(0.0)));
    live |= t ? 1u << j : 0u;
    n += t ? 1u : 0u;
  }
  if (n == 0u) return;
  uint at = atomicAdd(touchedCount, n);
  [[unroll]] for (uint j = 0u; j < kPerInvocation; ++j)
    if ((live & (1u << j)) != 0u) touched[at++] = pc.first4 + base + j;
}

#version 450
// The packed batch's size where later kernels can find it without a CPU round trip: the total
// sample count and a VkDispatchIndirectCommand for a per-sample kernel of `localSize` lanes, the
// groups split over x (at most maxGroupsX) and y.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 1) in;

layout(std430, binding = 0) readonly buffer Offsets { uint offsets[]; };  // numRays + 1
layout(std430, binding = 1) writeonly buffer Totals { uint totals[4]; };
#include "sampling/packed_totals.glsl"

#include "sampling/march_totals_shared.h"

void main() { writePackedTotals(offsets[pc.numRays], pc.localSize, pc.maxGroupsX); }

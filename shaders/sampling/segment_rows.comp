#version 450
// One segment of a training forward: lists the marched rows that the field must compute next. A ray
// whose first `from` samples (their field computed by the earlier segments) leave it short of its
// early-termination cut appends its samples [from, to) to `rows`, one atomic per ray; from = 0 lists
// every ray's first samples. Short of the cut means the compositor reaches sample `from`: the same
// sum of terminationDepth in the same order, so it composites only rows a segment computed
// (composite_forward.comp). The rays' order in the list varies from run to run; what a listed row
// computes does not.
#extension GL_GOOGLE_include_directive : require
#include "render/composite.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer RayOffsets { uint rayOffsets[]; };  // numRays + 1 (packed layout)
layout(std430, binding = 1) readonly buffer Samples { vec2 samples[]; };         // (t, delta)
layout(binding = 2, rgba32f) uniform readonly imageBuffer field;                // (r, g, b, sigma)
layout(std430, binding = 3) writeonly buffer Rows { uint rows[]; };
layout(std430, binding = 4) buffer Count { uint count; };                       // zeroed before

#include "sampling/segment_rows_shared.h"

void main() {
  uint ray = gl_GlobalInvocationID.x;
  if (ray >= pc.numRays) return;
  uint begin = rayOffsets[ray], n = rayOffsets[ray + 1u] - begin;
  uint first = begin + min(pc.from, n), last = begin + min(pc.to, n);
  if (first == last) return;
  float opaque = 0.0;
  uint i = begin;
  for (; i < first && opaque <= pc.maxOpticalDepth; ++i)
    opaque += terminationDepth(imageLoad(field, int(i)).w, samples[i].y);
  if (i < first || !(opaque <= pc.maxOpticalDepth)) return;
  uint at = atomicAdd(count, last - first);
  for (uint j = first; j < last; ++j) rows[at + (j - first)] = j;
}

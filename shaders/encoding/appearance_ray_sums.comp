#version 450
#extension GL_GOOGLE_include_directive : require
// Appearance embedding, backward, first pass: one invocation per ray sums dL/d(appearance columns)
// over the ray's rows of dDir (rowOffsets[r] to rowOffsets[r + 1]: every marched sample, or those
// kept before early termination) into raySums[r]. appearance_gradient.comp then sums these per
// photo. Summing a ray's rows here, with every lane busy, leaves the per-photo pass (whose lanes
// each meet only their own photo's rays, an eighth of a SIMD row busy or less) one read per ray.
layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer RowOffsets { uint rowOffsets[]; };  // ray -> its rows of dDir
layout(std430, binding = 1) readonly buffer DirGradient { vec4 dDir[]; };
layout(std430, binding = 2) writeonly buffer RaySums { vec4 raySums[]; };      // dimsVec4 per ray
layout(std430, binding = 3) readonly buffer RayCount { uint rayCount; };

#include "encoding/appearance_gradient_shared.h"

void main() {
  uint r = gl_GlobalInvocationID.x;
  if (r >= min(pc.maxRays, rayCount)) return;
  uint begin = rowOffsets[r], end = rowOffsets[r + 1u];
  for (uint k = 0u; k < pc.dimsVec4; ++k) {
    vec4 s = vec4(0.0);
    for (uint q = begin; q < end; ++q) s += dDir[q * pc.strideVec4 + pc.offsetVec4 + k];
    raySums[r * pc.dimsVec4 + k] = s;
  }
}

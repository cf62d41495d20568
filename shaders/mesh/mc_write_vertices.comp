#version 450
#extension GL_GOOGLE_include_directive : require
// Marching cubes, pass 2a: the vertex of each crossed edge of the chunk, where the linear
// interpolation of its two samples meets the threshold (ref::edgeVertex, same operations).
#include "mesh/marching_cubes.glsl"

layout(std430, binding = 0) readonly buffer Grid { float density[]; };
layout(std430, binding = 1) readonly buffer EdgeRanks { uint edgeRanks[]; };
layout(std430, binding = 2) readonly buffer EdgeBases { uint edgeBases[]; };
layout(std430, binding = 3) writeonly buffer Positions { float positions[]; };  // xyz per vertex

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  uint e = pc.first + i, s = e / 3u, axis = e % 3u;
  uvec3 idx = sampleIndex(s);
  if (idx[axis] + 1u >= pc.n[axis]) return;
  float a = density[s], b = density[s + sampleStrides()[axis]];
  if (insideSurface(a) == insideSurface(b)) return;
  precise float t = (pc.threshold - a) / (b - a);
  if (!(t >= 0.0 && t <= 1.0)) t = 0.5;  // a NaN or infinite sample: the edge's middle
  uint v = edgeRanks[e] + edgeBases[e / pc.chunk];
  for (uint k = 0u; k < 3u; ++k) {
    precise float p = pc.origin[k] + pc.spacing[k] * (float(idx[k]) + (k == axis ? t : 0.0));
    positions[3u * v + k] = p;
  }
}

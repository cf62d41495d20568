#version 450
#extension GL_GOOGLE_include_directive : require
// Marching cubes, pass 1a: 1 for each grid edge of the chunk whose samples lie on opposite sides of
// the threshold (it carries a vertex), else 0. Their scan numbers the vertices: welded by edge.
#include "mesh/marching_cubes.glsl"

layout(std430, binding = 0) readonly buffer Grid { float density[]; };
layout(std430, binding = 1) writeonly buffer Flags { uint flags[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  uint e = pc.first + i, s = e / 3u, axis = e % 3u;
  bool crossed = false;
  if (sampleIndex(s)[axis] + 1u < pc.n[axis])
    crossed = insideSurface(density[s]) != insideSurface(density[s + sampleStrides()[axis]]);
  flags[i] = crossed ? 1u : 0u;
}

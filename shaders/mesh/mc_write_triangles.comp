#version 450
#extension GL_GOOGLE_include_directive : require
// Marching cubes, pass 2b: the triangles of each cell of the chunk, from its case in the table,
// as ids of the vertices on their grid edges.
#include "mesh/marching_cubes.glsl"

layout(std430, binding = 0) readonly buffer Grid { float density[]; };
layout(std430, binding = 1) readonly buffer Table { uint table[]; };
layout(std430, binding = 2) readonly buffer EdgeRanks { uint edgeRanks[]; };
layout(std430, binding = 3) readonly buffer EdgeBases { uint edgeBases[]; };
layout(std430, binding = 4) readonly buffer CellRanks { uint cellRanks[]; };
layout(std430, binding = 5) readonly buffer CellBases { uint cellBases[]; };
layout(std430, binding = 6) writeonly buffer Triangles { uint triangles[]; };  // 3 vertex ids each

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  uint c = pc.first + i, base = cellSample(c), config = 0u;
  for (uint k = 0u; k < 8u; ++k) config |= (insideSurface(density[cornerSample(base, k)]) ? 1u : 0u) << k;
  uint entry = config * kTableStride, corners = 3u * table[entry];
  uint out0 = 3u * (cellRanks[c] + cellBases[c / pc.chunk]);
  for (uint j = 0u; j < corners; ++j) {
    uint cubeEdge = table[entry + 1u + j];
    uint edge = 3u * cornerSample(base, kCubeEdgeCorner[cubeEdge]) + cubeEdge / 4u;
    triangles[out0 + j] = edgeRanks[edge] + edgeBases[edge / pc.chunk];
  }
}

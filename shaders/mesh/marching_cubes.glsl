// Shared by the mc_*.comp kernels; tests/reference/mesh/marching_cubes.cpp is their CPU twin. Grid
// edge e = 3 * sample + axis runs from `sample` along `axis`; cells are numbered like samples over
// (n - 1) per axis. Edge flags and cell triangle counts are scanned in chunks of `chunk` elements,
// each chunk from 0, so an element's rank is its chunk's scan plus that chunk's base.
#ifndef VKNERF_MARCHING_CUBES_GLSL
#define VKNERF_MARCHING_CUBES_GLSL

layout(local_size_x = 256) in;

#include "mesh/marching_cubes_shared.h"

const uint kTableStride = 16u;  // core::kMcTableStride
// core::kCubeEdgeCorner: cube edge e runs along axis e / 4 from this corner.
const uint kCubeEdgeCorner[12] = uint[12](0u, 2u, 4u, 6u, 0u, 1u, 4u, 5u, 0u, 1u, 2u, 3u);

// NaN compares false: outside (ref::insideSurface).
bool insideSurface(float density) { return density >= pc.threshold; }

uvec3 sampleIndex(uint s) { return uvec3(s % pc.n.x, (s / pc.n.x) % pc.n.y, s / (pc.n.x * pc.n.y)); }
uvec3 sampleStrides() { return uvec3(1u, pc.n.x, pc.n.x * pc.n.y); }

// The lowest sample of cell c.
uint cellSample(uint c) {
  uvec3 cells = pc.n.xyz - 1u;
  uvec3 i = uvec3(c % cells.x, (c / cells.x) % cells.y, c / (cells.x * cells.y));
  return i.x + pc.n.x * (i.y + pc.n.y * i.z);
}

uint cornerSample(uint base, uint corner) {
  return base + (corner & 1u) + pc.n.x * (((corner >> 1u) & 1u) + pc.n.y * ((corner >> 2u) & 1u));
}

#endif

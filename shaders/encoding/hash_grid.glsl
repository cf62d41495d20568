// Cell lookup of the multiresolution hash grid, shared by encode_hash.comp and
// encode_hash_backward.comp. The arithmetic matches ref::hashGridCorners (tests/reference/encoding/hash_encoding.h)
// step for step, which documents the layout.
#ifndef VKNERF_HASH_GRID_GLSL
#define VKNERF_HASH_GRID_GLSL

// Cell of p at a level of `res` cells per axis and the position inside it, w in [0, 1]^3.
// min() after the conversion bounds the cell even for NaN or out-of-box input, so a bad position
// can give a bad feature but never an out-of-range table access.
void hashGridCell(vec3 p, uint res, out uvec3 cell, out vec3 w) {
  vec3 x = clamp((p + 1.0) * 0.5, 0.0, 1.0) * float(res);
  cell = min(uvec3(floor(x)), uvec3(res - 1u));
  w = x - vec3(cell);
}

// Table index (within the level) of vertex v: dense row-major for coarse levels, else the spatial hash.
uint hashGridIndex(uvec3 v, uint res, bool dense, uint log2Table) {
  if (dense) return v.x + (res + 1u) * (v.y + (res + 1u) * v.z);
  return (v.x ^ v.y * 2654435761u ^ v.z * 805459861u) & ((1u << log2Table) - 1u);
}

// Trilinear weight of corner k (bit0: +x, bit1: +y, bit2: +z), multiplied in ref's order.
float hashGridWeight(uint k, vec3 w) {
  float wx = (k & 1u) != 0u ? w.x : 1.0 - w.x;
  float wy = (k & 2u) != 0u ? w.y : 1.0 - w.y;
  float wz = (k & 4u) != 0u ? w.z : 1.0 - w.z;
  return wx * wy * wz;
}

#endif

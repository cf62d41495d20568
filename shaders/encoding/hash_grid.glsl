// Cell lookup of the multiresolution hash grid, shared by encode_hash.comp and
// encode_hash_backward.comp. The arithmetic matches ref::hashGridCorners (tests/reference/encoding/hash_encoding.h)
// step for step, which documents the layout.
#ifndef VKNERF_HASH_GRID_GLSL
#define VKNERF_HASH_GRID_GLSL

// mip-NeRF 360's scene contraction with the max norm (nerfacto's), when the grid spans a box of
// nested cascades (scale S = CONTRACT > 0): q = S p puts the inner cube at [-1, 1]^3, which stays
// as it is; beyond it q maps to (2 - 1/m) q / m, m = |q|_inf, so the outer cascades, each twice the
// last, share what is left up to 2 (the grid's cells shrink toward the inner cube, where the cameras
// look). Halved into the grid's [-1, 1]^3. ref::hashGridContract (tests/reference/encoding/hash_encoding.h).
vec3 hashGridContract(vec3 p, uint scale) {
  if (scale == 0u) return p;
  vec3 q = p * float(scale);
  float m = max(abs(q.x), max(abs(q.y), abs(q.z)));
  return 0.5 * (m <= 1.0 ? q : (2.0 - 1.0 / m) / m * q);
}

// dL/dp from dL/dc, c = hashGridContract(p, scale): the chain rule through the contraction. Beyond
// the inner cube c_i = (2/m - 1/m^2) q_i, and m moves with the largest axis k alone (sign s_k):
//   dL/dq_j = (2/m - 1/m^2) g_j + [j = k] s_k (2/m^3 - 2/m^2) sum_i g_i q_i.
vec3 hashGridContractGradient(vec3 p, uint scale, vec3 g) {
  if (scale == 0u) return g;
  float s = float(scale);
  vec3 q = p * s, a = abs(q);
  float m = max(a.x, max(a.y, a.z));
  if (m <= 1.0) return 0.5 * s * g;
  vec3 dq = (2.0 / m - 1.0 / (m * m)) * g;
  float radial = dot(g, q) * (2.0 / (m * m * m) - 2.0 / (m * m));
  uint k = a.x >= a.y && a.x >= a.z ? 0u : (a.y >= a.z ? 1u : 2u);
  dq[k] += (q[k] < 0.0 ? -radial : radial);
  return 0.5 * s * dq;
}

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

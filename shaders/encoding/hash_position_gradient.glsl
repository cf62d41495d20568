// The hash encoding's gradient with respect to the position, shared by
// encode_hash_position_gradient.comp and encode_hash_backward_position.comp. Within a cell a
// feature is trilinear in the cell coordinate w = (p + 1) / 2 * res - cell, so its derivative along
// an axis is the difference of the corner values weighted by the other two axes' weights, times
// res / 2. Outside the grid the forward clamps p, which makes the feature flat there: dL/dp = 0 on
// that axis. The includer declares `table` (imageBuffer of vec4) and the hash_grid_shared.h
// constants, and GROUP as encode_hash.comp groups levels.
#ifndef VKNERF_HASH_POSITION_GRADIENT_GLSL
#define VKNERF_HASH_POSITION_GRADIENT_GLSL

// dL/dfeatures of level lg of the group (d, d2) dotted with the table entry's features.
float hashEntryDot(uint entry, uint lg, vec4 d, vec4 d2) {
  if (FEATURES == 1u) return d[lg] * imageLoad(table, int(entry >> 2u))[entry & 3u];
  if (FEATURES == 2u) {
    vec4 t = imageLoad(table, int(entry >> 1u));
    vec2 e = (entry & 1u) != 0u ? t.zw : t.xy;
    return d[2u * lg] * e.x + d[2u * lg + 1u] * e.y;
  }
  if (FEATURES == 4u) return dot(d, imageLoad(table, int(entry)));
  return dot(d, imageLoad(table, int(2u * entry))) + dot(d2, imageLoad(table, int(2u * entry + 1u)));
}

// d(corner k's trilinear weight)/dw (bit0: +x, bit1: +y, bit2: +z).
vec3 hashCornerSlope(uint k, vec3 w) {
  vec3 s = vec3((k & 1u) != 0u ? 1.0 : -1.0, (k & 2u) != 0u ? 1.0 : -1.0, (k & 4u) != 0u ? 1.0 : -1.0);
  float wx = (k & 1u) != 0u ? w.x : 1.0 - w.x;
  float wy = (k & 2u) != 0u ? w.y : 1.0 - w.y;
  float wz = (k & 4u) != 0u ? w.z : 1.0 - w.z;
  return s * vec3(wy * wz, wx * wz, wx * wy);
}

// The clamp in hashGridCell: flat outside [-1, 1] on each axis.
vec3 hashClampedGradient(vec3 p, vec3 grad) {
  return grad * vec3(greaterThan(p, vec3(-1.0))) * vec3(lessThan(p, vec3(1.0)));
}

#endif

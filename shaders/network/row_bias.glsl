// A bias per row added to a dense layer's pre-activation before its activation (the fast model's
// per-photo appearance, src/models/common/appearance.h): row r adds row t(r) of a table of N4 floats
// a row, t(r) = rayTable[rowRay[r]].x (ROW_BIAS_PER_RAY: the row's sample's ray, then that ray's
// photo) or 0 for every row (ROW_BIAS_ONE: a render's one vector). The includer defines
// ROW_BIAS_BINDING (three bindings from it) and the constant ROW_BIAS; with ROW_BIAS_NONE the
// bindings are never read and the layer's arithmetic is unchanged.
#ifndef VKNERF_ROW_BIAS_GLSL
#define VKNERF_ROW_BIAS_GLSL
#include "network/row_bias_shared.h"

// The table as a texel buffer: imageLoad is vectorised on lavapipe, where a per-lane SSBO load is a
// loop over the lanes (shared/LAVAPIPE.md), and a colour layer reads W/8 of them a row.
layout(binding = ROW_BIAS_BINDING, rgba32f) uniform readonly imageBuffer RowBiasTable;
layout(std430, binding = ROW_BIAS_BINDING + 1) readonly buffer RowBiasRay { uint rowBiasRay[]; };
layout(std430, binding = ROW_BIAS_BINDING + 2) readonly buffer RowBiasRayTable { uvec2 rowBiasRayTable[]; };

// The table row that `row` (a row the dispatch computes) adds.
uint rowBiasRow(uint row) { return ROW_BIAS == ROW_BIAS_PER_RAY ? rowBiasRayTable[rowBiasRay[row]].x : 0u; }

// Columns [4 q, 4 q + 4) of table row t (N4 floats a row).
vec4 rowBias(uint t, uint q, uint N4) { return imageLoad(RowBiasTable, int(t * (N4 / 4u) + q)); }

#endif

#version 450
#extension GL_GOOGLE_include_directive : require
// One dense layer, backward to its weights (network/mlp_dense_dw.glsl):
// subgroupAdd, then compare-and-swap adds.
#define DW_COMPARE_SWAP
#include "network/mlp_dense_dw.glsl"

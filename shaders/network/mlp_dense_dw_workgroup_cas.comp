#version 450
#extension GL_GOOGLE_include_directive : require
// One dense layer, backward to its weights (network/mlp_dense_dw.glsl):
// a workgroup reduction in shared memory, then compare-and-swap adds.
#define DW_WORKGROUP_REDUCE
#define DW_COMPARE_SWAP
#include "network/mlp_dense_dw.glsl"

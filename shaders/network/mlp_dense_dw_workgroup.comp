#version 450
#extension GL_GOOGLE_include_directive : require
// One dense layer, backward to its weights (network/mlp_dense_dw.glsl):
// a workgroup reduction in shared memory, then float atomicAdd.
#define DW_WORKGROUP_REDUCE
#include "network/mlp_dense_dw.glsl"

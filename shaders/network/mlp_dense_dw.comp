#version 450
#extension GL_GOOGLE_include_directive : require
// One dense layer, backward to its weights (network/mlp_dense_dw.glsl):
// subgroupAdd, then float atomicAdd.
#include "network/mlp_dense_dw.glsl"

#version 450
#extension GL_GOOGLE_include_directive : require
// Multiresolution hash encoding, backward to the table (encoding/encode_hash_backward.glsl).
#include "encoding/encode_hash_backward.glsl"

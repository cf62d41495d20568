#version 450
#extension GL_GOOGLE_include_directive : require
// Multiresolution hash encoding, backward to the table and to the position in one pass, each add
// into the table a compare-and-swap loop (HashBackwardMode::CompareSwap;
// encoding/encode_hash_backward.glsl): no float atomics.
#define HASH_COMPARE_SWAP
#define HASH_POSITION_GRADIENT
#include "encoding/encode_hash_backward.glsl"

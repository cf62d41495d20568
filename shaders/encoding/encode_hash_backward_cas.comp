#version 450
#extension GL_GOOGLE_include_directive : require
// Multiresolution hash encoding, backward to the table, each add a compare-and-swap loop
// (HashBackwardMode::CompareSwap; encoding/encode_hash_backward.glsl): no float atomics.
#define HASH_COMPARE_SWAP
#include "encoding/encode_hash_backward.glsl"

#version 450
#extension GL_GOOGLE_include_directive : require
// Multiresolution hash encoding, backward to the table and to the position in one pass
// (encoding/encode_hash_backward.glsl): camera refinement's dL/dp from the corners the table's
// backward visits anyway, rather than a second pass over them (encode_hash_position_gradient.comp).
#define HASH_POSITION_GRADIENT
#include "encoding/encode_hash_backward.glsl"

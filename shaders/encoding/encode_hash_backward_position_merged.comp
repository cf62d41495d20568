#version 450
#extension GL_GOOGLE_include_directive : require
// Multiresolution hash encoding, backward to the table and to the position in one pass, a
// subgroup's adds into one entry merged (HashBackwardMode::SubgroupMerged;
// encoding/encode_hash_backward.glsl).
#define HASH_POSITION_GRADIENT
#define HASH_SUBGROUP_MERGE
#include "encoding/encode_hash_backward.glsl"

#version 450
#extension GL_GOOGLE_include_directive : require
// Exclusive prefix sum, last step of each level: adds the scanned total of all earlier blocks of
// 1024 (scan_blocks.comp) to every output of a block, clamping to `clampTo`.
layout(local_size_x = 256) in;

layout(std430, binding = 0) buffer Out { uint outputs[]; };
layout(std430, binding = 1) readonly buffer BlockOffsets { uint blockOffsets[]; };

#include "gpu/scan_add_shared.h"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.outputCount) return;
  outputs[i] = min(outputs[i] + blockOffsets[i / 1024u], pc.clampTo);
}

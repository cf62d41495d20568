#version 450
// Occupancy update, step 3: d = max(d * decay, fresh) for every cell (cells not sampled this time
// see fresh = 0 and only decay, as in instant-ngp), then the occupancy bits d > threshold. One
// invocation per 32-cell word, so bits are written whole, without atomics. With capAtMean the
// threshold is min(threshold, the mean density occupancy_mean.comp wrote before this update).
#extension GL_GOOGLE_include_directive : require
#include "occupancy/occupancy.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Density { float gridDensity[]; };
layout(std430, binding = 1) readonly buffer Fresh { uint freshBits[]; };
layout(std430, binding = 2) writeonly buffer Bits { uint occupancyBits[]; };
layout(std430, binding = 3) readonly buffer Mean { float meanDensity; };

#include "occupancy/occupancy_ema_shared.h"

void main() {
  uint w = flatIndex(64u);
  if (w * 32u >= pc.numCells) return;
  float threshold = pc.capAtMean != 0u ? min(pc.threshold, meanDensity) : pc.threshold;
  uint word = 0u;
  for (uint b = 0u; b < 32u; ++b) {
    uint i = w * 32u + b;
    if (i >= pc.numCells) break;
    float d = emaDensity(gridDensity[i], pc.decay, uintBitsToFloat(freshBits[i]));
    gridDensity[i] = d;
    if (d > threshold) word |= 1u << b;
  }
  occupancyBits[w] = word;
}

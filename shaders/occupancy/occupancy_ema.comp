#version 450
// Occupancy update, step 3: d = max(d * decay, fresh) for every cell (cells not sampled this time
// see fresh = 0 and only decay, as in instant-ngp), then the occupancy bits d > threshold. One
// invocation per 32-cell word, so bits are written whole, without atomics. With capAtMean the
// threshold is min(threshold, the mean density occupancy_mean.comp wrote before this update).
// The word's cells are read and written as 8 vec4s in an unrolled loop: on lavapipe a float at a
// per-lane address is a scalar loop over the lanes, a vec4 costs about half as much a float, and a
// dynamic loop masks every write (shared/LAVAPIPE.md); on a GPU a lane reads 128 contiguous bytes.
// The density and fresh buffers hold whole words (OccupancyGrid pads them with zeros), and the
// bits of the padding cells are cleared. Each word's sum of its new densities (as the mean counts
// them: occupancyMeanTerm) goes to wordSums, so that the next update's mean reads one float a word
// instead of every cell again (occupancy_mean.comp).
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "occupancy/occupancy.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer Density { vec4 gridDensity4[]; };
layout(std430, binding = 1) readonly buffer Fresh { uvec4 freshBits4[]; };
layout(std430, binding = 2) writeonly buffer Bits { uint occupancyBits[]; };
layout(std430, binding = 3) readonly buffer Mean { float meanDensity; };
layout(std430, binding = 4) writeonly buffer WordSums { float wordSums[]; };

#include "occupancy/occupancy_ema_shared.h"

void main() {
  uint w = flatIndex(64u);
  if (w * 32u >= pc.numCells) return;
  float threshold = pc.capAtMean != 0u ? min(pc.threshold, meanDensity) : pc.threshold;
  uint word = 0u;
  float sum = 0.0;
  [[unroll]] for (uint q = 0u; q < 8u; ++q) {
    uint j = w * 8u + q;
    vec4 old = gridDensity4[j];
    vec4 fresh = uintBitsToFloat(freshBits4[j]);
    vec4 d = vec4(emaDensity(old.x, pc.decay, fresh.x), emaDensity(old.y, pc.decay, fresh.y),
                  emaDensity(old.z, pc.decay, fresh.z), emaDensity(old.w, pc.decay, fresh.w));
    gridDensity4[j] = d;
    uvec4 on = uvec4(greaterThan(d, vec4(threshold)));
    word |= (on.x | (on.y << 1u) | (on.z << 2u) | (on.w << 3u)) << (4u * q);
    sum += occupancyMeanTerm(d);
  }
  uint cells = pc.numCells - w * 32u;  // the last word may be partial
  if (cells < 32u) word &= (1u << cells) - 1u;
  occupancyBits[w] = word;
  wordSums[w] = sum;
}

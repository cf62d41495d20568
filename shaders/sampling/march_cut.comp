#version 450
// A packed batch cut to whole rays on the device (PackedLayout::recordCutToWholeRays): when the
// batch reached the sample capacity the offsets were clamped there, so the rays from the first one
// that ends at the capacity on were cut short. The batch keeps the whole rays, rounded down to a
// multiple of rayAlign (at least rayAlign, which the capacity always holds whole), and the offsets
// of every later ray are emptied at the kept total, so that ray has no samples, no colour but the
// background, and no gradient. Writes the totals for the kept samples and `whole[0]`: the rays kept.
// A batch under the capacity keeps every ray (all numRays).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 256) in;

layout(std430, binding = 0) buffer Offsets { uint offsets[]; };  // numRays + 1
layout(std430, binding = 1) buffer Totals { uint totals[4]; };
layout(std430, binding = 2) writeonly buffer Whole { uint whole[]; };
#include "sampling/packed_totals.glsl"

#include "sampling/march_cut_shared.h"

shared uint keptRays, keptSamples;

void main() {
  uint lane = gl_LocalInvocationID.x;
  if (lane == 0u) {
    uint rays = pc.numRays;
    if (offsets[pc.numRays] >= pc.capacity) {
      // The rays r whose end offsets[r + 1] lies below the capacity (offsets never decrease).
      uint lo = 0u, hi = pc.numRays;
      while (lo < hi) {
        uint mid = (lo + hi) / 2u;
        if (offsets[mid + 1u] < pc.capacity) lo = mid + 1u; else hi = mid;
      }
      rays = min(max(pc.rayAlign, lo / pc.rayAlign * pc.rayAlign), pc.numRays);
    }
    keptRays = rays;
    keptSamples = offsets[rays];
  }
  barrier();
  uint rays = keptRays, total = keptSamples;
  for (uint r = rays + 1u + lane; r <= pc.numRays; r += gl_WorkGroupSize.x) offsets[r] = total;
  if (lane == 0u) {
    writePackedTotals(total, pc.localSize, pc.maxGroupsX);
    whole[0] = rays;
  }
}

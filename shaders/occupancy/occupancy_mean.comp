#version 450
// The grid's mean density (instant-ngp caps the occupancy threshold at it, so that a young field
// whose densities are all small is not declared empty everywhere), on the device so that an update
// needs no read-back. Two dispatches: pass 0, workgroup g sums its chunk of the terms into
// partials[g] (each lane a strided share, then a tree in shared memory); pass 1, one workgroup sums
// the kOccupancyMeanGroups partials and divides. Many workgroups, because one alone runs on one
// core of a CPU device and one multiprocessor of a GPU (it took 60 ms a grid update on 8.4 M cells);
// no atomics, so the result is the same bits every time. Non-finite densities, and the -1 of a cell
// no training camera sees (occupancy_mark_unseen), count as 0 (occupancyMeanTerm).
// The terms: with pc.fromWordSums the sums of 32 cells occupancy_ema.comp wrote as it last set the
// densities (one float a word: 8.4 M cells are 262 k words), else the cells themselves, read as
// vec4s (a float at a per-lane address is a scalar loop over the lanes on lavapipe, a vec4 about
// half as dear a float) at consecutive vec4s across the lanes (coalesced on a GPU); the buffer holds
// whole 32-cell words whose padding is 0 (OccupancyGrid), so the last vec4 adds no other cell.
#extension GL_GOOGLE_include_directive : require
#include "occupancy/occupancy.glsl"
#include "occupancy/occupancy_mean_shared.h"

layout(local_size_x = kOccupancyMeanGroups) in;

layout(std430, binding = 0) readonly buffer Density { vec4 gridDensity4[]; };
layout(std430, binding = 1) buffer Partials { float partials[]; };  // kOccupancyMeanGroups
layout(std430, binding = 2) writeonly buffer Mean { float meanDensity; };
layout(std430, binding = 3) readonly buffer WordSums { float wordSums[]; };

shared float sums[kOccupancyMeanGroups];

void main() {
  uint l = gl_LocalInvocationID.x;
  float s = 0.0;
  if (pc.pass == 0u) {
    uint terms = pc.fromWordSums != 0u ? (pc.numCells + 31u) / 32u : (pc.numCells + 3u) / 4u;
    uint begin = gl_WorkGroupID.x * pc.chunk, end = min(begin + pc.chunk, terms);
    if (pc.fromWordSums != 0u)
      for (uint i = begin + l; i < end; i += kOccupancyMeanGroups) s += wordSums[i];
    else
      for (uint i = begin + l; i < end; i += kOccupancyMeanGroups) s += occupancyMeanTerm(gridDensity4[i]);
  } else {
    s = partials[l];
  }
  sums[l] = s;
  barrier();
  for (uint h = kOccupancyMeanGroups / 2u; h > 0u; h >>= 1u) {
    if (l < h) sums[l] += sums[l + h];
    barrier();
  }
  if (l != 0u) return;
  if (pc.pass == 0u) partials[gl_WorkGroupID.x] = sums[0];
  else meanDensity = sums[0] / float(pc.numCells);
}

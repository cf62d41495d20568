// The push constants of occupancy_mean.comp; on the host, vknerf::glsl::OccupancyMeanPush.
#ifndef VKNERF_OCCUPANCY_OCCUPANCY_MEAN_SHARED_H
#define VKNERF_OCCUPANCY_OCCUPANCY_MEAN_SHARED_H
#include "common/shared_types.h"

// Workgroups of pass 0, partials pass 1 adds, and lanes of each workgroup (a power of two).
#define kOccupancyMeanGroups 256u

PUSH_CONSTANTS_BEGIN(OccupancyMeanPush)
  uint numCells;
  uint chunk;         // terms a workgroup of pass 0 sums: ceil(terms / kOccupancyMeanGroups)
  uint pass;          // 0: partial sums, 1: their sum over numCells
  uint fromWordSums;  // 1: a term is a word's sum (occupancy_ema.comp), 0: a vec4 of cells
PUSH_CONSTANTS_END

#endif

// The push constants of occupancy_mean.comp; on the host, vknerf::glsl::OccupancyMeanPush.
#ifndef VKNERF_OCCUPANCY_OCCUPANCY_MEAN_SHARED_H
#define VKNERF_OCCUPANCY_OCCUPANCY_MEAN_SHARED_H
#include "common/shared_types.h"

// Workgroups of pass 0, partials pass 1 adds, and lanes of each workgroup (a power of two).
#define kOccupancyMeanGroups 256u

PUSH_CONSTANTS_BEGIN(OccupancyMeanPush)
  uint numCells;
  uint chunk;  // cells a workgroup of pass 0 sums: ceil(numCells / kOccupancyMeanGroups)
  uint pass;   // 0: partial sums, 1: their sum over numCells
PUSH_CONSTANTS_END

#endif

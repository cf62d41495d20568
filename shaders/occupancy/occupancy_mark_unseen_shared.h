// The push constants of occupancy_mark_unseen.comp; on the host, vknerf::glsl::OccupancyUnseenPush.
#ifndef VKNERF_OCCUPANCY_OCCUPANCY_MARK_UNSEEN_SHARED_H
#define VKNERF_OCCUPANCY_OCCUPANCY_MARK_UNSEEN_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(OccupancyUnseenPush)
  uint resolution;
  uint cascades;
  uint numCells;
  uint numViews;
  float centre[3];      // of the box
  float halfExtent[3];  // of the box, per axis
PUSH_CONSTANTS_END

#endif

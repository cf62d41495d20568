// The push constants of accumulate_segment.comp; on the host, vknerf::glsl::SegmentPush.
#ifndef VKNERF_RENDER_ACCUMULATE_SEGMENT_SHARED_H
#define VKNERF_RENDER_ACCUMULATE_SEGMENT_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(SegmentPush)
  uint numRays;
  uint cap;    // the most samples a ray was marched this round
  uint first;  // 1: nothing gathered yet (every ray starts at T = 1)
  uint last;   // 1: every ray ends with this round
  float minTransmittance;
PUSH_CONSTANTS_END

#endif

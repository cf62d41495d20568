// The push constants of segment_rows.comp; on the host, vknerf::glsl::SegmentRowsPush.
#ifndef VKNERF_SAMPLING_SEGMENT_ROWS_SHARED_H
#define VKNERF_SAMPLING_SEGMENT_ROWS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(SegmentRowsPush)
  uint numRays;
  uint from, to;          // the segment: each ray's samples [from, to)
  float maxOpticalDepth;  // the compositor's early-termination depth (render/composite.glsl)
PUSH_CONSTANTS_END

#endif

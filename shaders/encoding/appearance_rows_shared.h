// The push constants of appearance_rows.comp; on the host, vknerf::glsl::AppearanceRowsPush. A
// photo's vector is dimsVec4 vec4s, row c of the table (the photos' vectors one after another).
#ifndef VKNERF_ENCODING_APPEARANCE_ROWS_SHARED_H
#define VKNERF_ENCODING_APPEARANCE_ROWS_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(AppearanceRowsPush)
  uint count;       // rows (samples)
  uint strideVec4;  // of the feature matrix
  uint offsetVec4;  // the vector's first column / 4
  uint dimsVec4;
  uint fixedRow;    // APPEARANCE_PER_RAY: each sample's ray's photo; else this row of the table for all
  uint limitBase;   // row_limit.glsl
PUSH_CONSTANTS_END

#define APPEARANCE_PER_RAY 0xffffffffu

#endif

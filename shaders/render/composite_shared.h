// The push constants of composite_backward.comp and composite_forward.comp; on the host, vknerf::glsl::CompositePush.
#ifndef VKNERF_RENDER_COMPOSITE_SHARED_H
#define VKNERF_RENDER_COMPOSITE_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(CompositePush)
  vec4 background;                // rgb, when useBackgroundBuffer == 0
  uint numRays;
  uint samplesPerRay;             // 0: packed layout through rayOffsets
  uint useBackgroundBuffer;
  float maxOpticalDepth;          // early termination; +inf: composite every sample
  uint writeKept;                 // forward: write the kept counts; unused by backward
  float distortion;               // backward: the distortion loss's weight per ray; 0: none
  float coneAngle, dtMin, dtMax;  // backward: the march's spacing (MarchSpacing), for the distortion loss
  uint writeTermValues;           // backward: write each ray's weighted loss terms (binding 9)
  uint distortionFarField;        // backward: the far field's weight T_final as the distortion loss's last interval
PUSH_CONSTANTS_END

#endif

// The push constants of sample_pdf.comp; on the host, vknerf::glsl::PdfPush.
#ifndef VKNERF_SAMPLING_SAMPLE_PDF_SHARED_H
#define VKNERF_SAMPLING_SAMPLE_PDF_SHARED_H
#include "common/shared_types.h"

PUSH_CONSTANTS_BEGIN(PdfPush)
  uint numRays;
  uint nCoarse;
  uint nFine;
  uint seed;
  uint jitter;
  float padding;
PUSH_CONSTANTS_END

#endif

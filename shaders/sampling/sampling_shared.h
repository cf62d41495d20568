// The specialization constants of sample_stratified.comp and sample_pdf.comp (through
// sampling/sampling.glsl); on the host, vknerf::glsl::SamplingSpec.
#ifndef VKNERF_SAMPLING_SAMPLING_SHARED_H
#define VKNERF_SAMPLING_SAMPLING_SHARED_H
#include "common/shared_types.h"

SPEC_CONSTANTS_BEGIN(SamplingSpec)
  SPEC_CONSTANT(0, uint, kLocalSize, 64)
  LOCAL_SIZE_X_ID(0)
SPEC_CONSTANTS_END

#endif

#pragma once
// Early termination of a packed batch once the field is known (shaders/sampling/march_truncate.comp,
// march_compact.comp): ray r keeps its samples while the transmittance in front of them is at
// least minTransmittance (default 1e-4), i.e. up to and including the sample where it drops
// below; the survivors are packed into the out* buffers (same layouts as RayMarcher's outputs,
// field vec4 (r, g, b, sigma) per sample, which the compositor takes as it is). The light the
// dropped samples could add is below minTransmittance times their brightest colour.
// It is a sampling stage rather than part of the compositor so that the backward passes, the
// expensive part, run over the survivors only.
#include <cstdint>

#include "gpu/buffer.h"
#include "gpu/kernel.h"
#include "gpu/recorder.h"
#include "nerf/sampling/packed_layout.h"

namespace vknerf::nerf {

class EarlyTermination {
 public:
  EarlyTermination(Context& ctx, uint32_t maxRays);
  void record(gpu::Recorder& rec, uint32_t numRays, const gpu::BufferRange& offsets, const gpu::BufferRange& samples,
              const gpu::BufferRange& sampleRay, const gpu::BufferRange& field, float minTransmittance,
              const gpu::BufferRange& outOffsets, const gpu::BufferRange& outSamples,
              const gpu::BufferRange& outSampleRay, const gpu::BufferRange& outField, const gpu::BufferRange& outTotals);
  // The optical depth the kernels compare against: -ln(minTransmittance), rounded to float.
  static float maxOpticalDepth(float minTransmittance);

 private:
  uint32_t maxRays_;
  PackedLayout layout_;  // counts: the samples each ray keeps
  gpu::Kernel truncate_, compact_;
};

}  // namespace vknerf::nerf

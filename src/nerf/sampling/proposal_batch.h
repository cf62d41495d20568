#pragma once
// What the proposal estimator's kernels read and write (nerf::ProposalSampler, nerf::InterlevelLoss),
// in the packed layout (nerf::PackedSamples): ray r owns entries [offsets[r], offsets[r+1]).
//   candidates   the march's samples (t, delta) and the proposal's activated density at each
//   samples      the samples the proposal places, the field's to evaluate: (t, delta), delta the
//                bin's length in occupied length (tests/reference/sampling/proposal.h)
// The offsets come from the device (a count, then a prefix sum), so the host cannot check the
// entries' buffers against them: whoever writes the offsets sizes those buffers for their totals.
#include "gpu/memory/buffer.h"

namespace vknerf::nerf {

struct ProposalCandidates {
  gpu::BufferRange offsets, samples, sigma;
};

struct ProposalSamples {
  gpu::BufferRange offsets, samples;
};

}  // namespace vknerf::nerf

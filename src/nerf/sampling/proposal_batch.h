#pragma once
// What the proposal estimator's kernels read (nerf::ProposalSampler, nerf::InterlevelLoss): a ray's
// candidates, the march's packed samples (nerf::PackedSamples: ray r owns [offsets[r], offsets[r+1])),
// and the proposal field at each, vec4 (r, g, b, sigma) as a field writes it (only sigma is read).
// The offsets come from the device, so the host cannot check the entries' buffers against them:
// whoever writes the offsets sizes those buffers for their totals.
#include "gpu/memory/buffer.h"

namespace vknerf::nerf {

struct ProposalCandidates {
  gpu::BufferRange offsets, samples, field;
};

}  // namespace vknerf::nerf

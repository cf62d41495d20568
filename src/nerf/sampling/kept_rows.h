#pragma once
// The samples the rays kept before early termination, packed for the backward pass
// (shaders/sampling/kept_rows.comp). The compositor writes each ray's kept count into counts();
// record() turns them into a packed batch: rows() gives each packed row's marched sample (the
// backward's gathered reads, shaders/gpu/row_gather.glsl), positions() that sample's position and
// total() their number, a uint on the device (the backward's row limit). A training step whose
// rays stop early then runs its backward over the kept samples only, instead of over every marched
// sample with a zero gradient behind each ray's cut.
#include <cstdint>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/sampling/packed_layout.h"

namespace vknerf::nerf {

class KeptRows {
 public:
  KeptRows(Context& ctx, uint32_t maxRays, uint32_t sampleCapacity);

  // uint per ray: the samples it kept (Compositor::recordForward's CompositeOutputs::keptCounts).
  const gpu::Buffer& counts() const { return layout_.counts(); }
  gpu::Buffer& counts() { return layout_.counts(); }
  // rayOffsets: the march's packed layout (numRays + 1); positions: vec4 per marched sample, bound
  // as a texel buffer. Throws vknerf::Error for numRays over maxRays or buffers too small.
  void record(gpu::Recorder& rec, uint32_t numRays, const gpu::BufferRange& rayOffsets,
              const gpu::BufferRange& positions);

  // The total alone (offsets and total(), no packing): for a step whose backward does not gather.
  void recordTotal(gpu::Recorder& rec, uint32_t numRays);

  const gpu::Buffer& rows() const { return rows_; }            // uint per packed row
  const gpu::Buffer& offsets() const { return offsets_; }      // numRays + 1: ray r's rows [off[r], off[r+1])
  const gpu::Buffer& positions() const { return positions_; }  // vec4 per packed row
  gpu::BufferRange total() const { return {totals_, 0, 4}; }   // uint: the packed rows
  const gpu::Buffer& totals() const { return totals_; }        // total() at byte 0

 private:
  uint32_t maxRays_, capacity_;
  PackedLayout layout_;
  gpu::Buffer offsets_, totals_, rows_, positions_;
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

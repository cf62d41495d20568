#pragma once
// A training forward in segments, so that the field is computed only where the compositor reads it
// (shaders/sampling/segment_rows.comp). Early termination stops a ray's compositing once it has
// turned opaque; a trained object keeps about a quarter of the samples it marches, yet one forward
// over every marched sample computes them all. Segment by segment, record() lists the marched rows
// of the rays still short of their cut: the field runs over those rows alone (read and written
// through the list, NerfRows::rowGather), and the next segment reads what it computed. Every row the
// compositor reads has been computed, with the same arithmetic as a forward over the whole batch;
// the rows behind a cut are left as they were.
#include <cstdint>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/sampling/packed_samples.h"

namespace vknerf::nerf {

class SegmentRows {
 public:
  SegmentRows(Context& ctx, uint32_t sampleCapacity);

  // Lists samples [from, to) of each of the `numRays` rays of `batch` whose first `from` samples,
  // with the densities in `field` (vec4 rgb, sigma per marched sample, a texel buffer), keep its
  // optical depth within maxOpticalDepth (Compositor::maxOpticalDepth); from = 0 lists every ray.
  // rows() and count() hold the list until the next record().
  void record(gpu::Recorder& rec, uint32_t numRays, const PackedSamples& batch, const gpu::BufferRange& field,
              float maxOpticalDepth, uint32_t from, uint32_t to);

  const gpu::Buffer& rows() const { return rows_; }          // uint per listed row: its marched row
  gpu::BufferRange count() const { return {count_, 0, 4}; }  // uint: the listed rows

 private:
  uint32_t capacity_;
  gpu::Buffer rows_, count_;
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

#pragma once
// Frequency (positional) encoding gamma(p) of vec4 inputs (shaders/encoding/encode_frequency.comp).
// Column order, per row (the released NeRF code's and the seed's §6.3 order):
//   [p_0 .. p_{D-1}]                                  if includeInput
//   for k in 0..L-1: [sin(2^k pi p_0) .. sin(2^k pi p_{D-1}), cos(2^k pi p_0) .. cos(2^k pi p_{D-1})]
// so positions (D = 3, L = 10) give 63 columns and directions (D = 3, L = 4) 27.
// The block is written into a row-major feature matrix (row stride a multiple of 4 floats) at a
// column offset that is a multiple of 4, as paddedDims() = outputDims() rounded up to 4 columns;
// the padding columns of the block are written as 0, columns outside the block are not touched.
// gamma(x) and gamma(d) can thus share one matrix at offsets 0 and paddedDims of the first.
#include <cstdint>

#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/encoding/encoding.h"

namespace vknerf::nerf {

class FrequencyEncoding final : public Encoding {
 public:
  // inputDims: components of each vec4 input used (1..4); levels: L (0..16).
  FrequencyEncoding(Context& ctx, uint32_t inputDims, uint32_t levels, bool includeInput);
  uint32_t outputDims() const override { return outputDims_; }
  uint32_t inputDims() const { return inputDims_; }
  uint32_t levels() const { return levels_; }
  bool includeInput() const { return includeInput_; }

  // rows.inputs: `count` vec4; rows.features: `count` rows of `stride` floats. stride and
  // columnOffset are multiples of 4 and columnOffset + paddedDims() <= stride. Every row is
  // encoded: no row limit or gather (the vanilla model's batches are full). No parameters:
  // `params` is not read.
  void recordForward(gpu::Recorder& rec, const EncodedRows& rows, const gpu::BufferRange& params) override;
  void recordForward(gpu::Recorder& rec, const EncodedRows& rows) { recordForward(rec, rows, {}); }

 private:
  Context& ctx_;
  uint32_t inputDims_, levels_, outputDims_;
  bool includeInput_;
  gpu::Kernel kernel_;
};

}  // namespace vknerf::nerf

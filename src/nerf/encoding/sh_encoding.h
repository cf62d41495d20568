#pragma once
// Spherical-harmonics direction encoding (shaders/encoding/encode_sh.comp): degree^2 real SH coefficients
// (16 for instant-ngp's degree 4) of each unit direction, basis and constants documented in
// tests/reference/encoding/sh_encoding.h. Written into a row-major feature matrix (row stride a multiple of 4
// floats) at a column offset that is a multiple of 4, as paddedDims() columns, padding 0 and
// columns outside the block untouched. No backward: directions are not optimised.
#include <cstdint>

#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/limited_dispatch.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/encoding/encoding.h"

namespace vknerf::nerf {

class ShEncoding final : public Encoding {
 public:
  explicit ShEncoding(Context& ctx, uint32_t degree = 4);  // degree: 1..4 bands
  uint32_t degree() const { return degree_; }
  uint32_t outputDims() const override { return degree_ * degree_; }

  // rows.inputs: `count` vec4 directions (xyz unit, w ignored; texel-buffer aligned offset);
  // rows.features: the block written (nerf/encoding/encoded_rows.h); rows at and past
  // rows.rowLimit are left untouched. No parameters: `params` is not read.
  void recordForward(gpu::Recorder& rec, const EncodedRows& rows, const gpu::BufferRange& params) override;
  void recordForward(gpu::Recorder& rec, const EncodedRows& rows) { recordForward(rec, rows, {}); }

 private:
  Context& ctx_;
  uint32_t degree_;
  gpu::Kernel kernel_;
  gpu::LimitedDispatch limited_;
};

}  // namespace vknerf::nerf

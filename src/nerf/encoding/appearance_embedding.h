#pragma once
// The appearance embedding's kernels (shaders/encoding/appearance_*.comp): a learned vector of
// dims() floats per training photo (exposure, white balance: what differs from photo to photo),
// written into the colour network's direction input beside the SH encoding, and its gradient summed
// per photo from dL/d(direction input). The table itself is a model's trainable parameters
// (models/common/appearance.h). CPU twin: src/reference/encoding/appearance.h.
#include <cstdint>
#include <optional>

#include "gpu/kernel.h"
#include "gpu/limited_dispatch.h"
#include "gpu/recorder.h"

namespace vknerf::nerf {

// The rows the vectors are written into: `count` rows of a feature matrix of `stride` floats, the
// vector at `columnOffset` (both multiples of 4), rows at and past rowLimit (a uint on the device)
// untouched. Training: pixelIds (uvec2 (photo, pixel) per ray) and sampleRay (uint per row) pick
// each row's photo; a render gives fixedRow instead.
struct AppearanceRows {
  uint32_t count = 0;
  gpu::BufferRange features;
  uint32_t stride = 0, columnOffset = 0;
  std::optional<gpu::BufferRange> rowLimit;
  std::optional<gpu::BufferRange> pixelIds, sampleRay;
  uint32_t fixedRow = 0;  // with neither: every row gets this row of the table
};

// What the gradient reads of a trained batch: `rays` rays' pixel ids, the rays in runs of one photo
// each (RayGeneration::RandomPixels::inCameraRuns, over the numPhotos the gradient is for), ray r's
// rows of dDir being [rowOffsets[r], rowOffsets[r + 1]) (stride and columnOffset as
// AppearanceRows), rayCount a uint on the device (the rays that trained).
struct AppearanceGradientInputs {
  uint32_t rays = 0;
  gpu::BufferRange pixelIds, rowOffsets, dDir, rayCount;
  uint32_t stride = 0, columnOffset = 0;
};

class AppearanceEmbedding {
 public:
  // dims: a multiple of 4, 4..kMaxDims.
  static constexpr uint32_t kMaxDims = 64;  // appearance_gradient.comp's shared sums: 16 vec4 a lane
  AppearanceEmbedding(Context& ctx, uint32_t dims);
  uint32_t dims() const { return dims_; }

  void recordRows(gpu::Recorder& rec, const AppearanceRows& rows, const gpu::BufferRange& table);
  // grads (dims floats per photo, written) = the sum of the photo's rows of dDir.
  void recordGradient(gpu::Recorder& rec, const AppearanceGradientInputs& in, uint32_t numPhotos,
                      const gpu::BufferRange& grads);
  // mean (dims floats) = the mean of the table's numPhotos vectors.
  void recordMean(gpu::Recorder& rec, uint32_t numPhotos, const gpu::BufferRange& table, const gpu::BufferRange& mean);

 private:
  Context& ctx_;
  uint32_t dims_;
  gpu::Kernel rows_, gradient_, mean_;
  gpu::LimitedDispatch limited_;
  uint32_t maxGroups_;  // of the per-photo sums' dispatch
};

}  // namespace vknerf::nerf

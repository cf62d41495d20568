#pragma once
// The appearance embedding's kernels (shaders/encoding/appearance_*.comp): a learned vector of
// dims() floats per training photo (exposure, white balance: what differs from photo to photo) and
// its weights W_a (dims() rows of the colour layer's width). The vector enters the colour network as
// the bias a W_a on the colour layer's pre-activation: the same function as the vector beside the
// direction encoding in the layer's input, without widening the layer or writing the vector into
// every sample's row (a sample adds its photo's bias, nerf::RowBias). Their gradients come from the
// per-photo sums of dL/d(colour pre-activation). The parameters themselves are a model's
// (models/common/appearance.h). CPU twin: tests/reference/encoding/appearance.h.
#include <cstdint>

#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"

namespace vknerf::nerf {

// What the gradient reads of a trained batch: `rays` rays' pixel ids, the rays in runs of one photo
// each (RayGeneration::RandomPixels::inCameraRuns, over the photos the gradient is for), ray r's rows
// of dColour (the colour layer's pre-activation gradient, width floats a row) being
// [rowOffsets[r], rowOffsets[r + 1]), rayCount a uint on the device (the rays that trained).
struct AppearanceGradientInputs {
  uint32_t rays = 0;
  gpu::BufferRange pixelIds, rowOffsets, dColour, rayCount;
};

// The parameters the kernels read and the gradients they write: vectors (dims floats per photo),
// weights W_a (dims rows of width floats), and their gradients alike; photoSums: width floats per
// photo, scratch between the two gradient kernels.
struct AppearanceParameters {
  gpu::BufferRange vectors, weights;
};
struct AppearanceGradients {
  gpu::BufferRange vectors, weights, photoSums;
};

class AppearanceEmbedding {
 public:
  // dims: a multiple of 4, 4..kMaxDims; width: the colour layer's, a multiple of 4 up to kMaxWidth.
  static constexpr uint32_t kMaxDims = 64;
  static constexpr uint32_t kMaxWidth = 64;  // appearance_gradient.comp's shared sums: 16 vec4 a lane
  AppearanceEmbedding(Context& ctx, uint32_t dims, uint32_t width);
  uint32_t dims() const { return dims_; }
  uint32_t width() const { return width_; }

  // bias rows [0, count) (width floats each) = vectors [first, first + count) times W_a.
  void recordBias(gpu::Recorder& rec, const AppearanceParameters& p, uint32_t first, uint32_t count,
                  const gpu::BufferRange& bias);
  // The gradients of the numPhotos vectors and of W_a (written) from a trained batch.
  void recordGradient(gpu::Recorder& rec, const AppearanceGradientInputs& in, uint32_t numPhotos,
                      const AppearanceParameters& p, const AppearanceGradients& g);
  // mean (dims floats) = the mean of the table's numPhotos vectors.
  void recordMean(gpu::Recorder& rec, uint32_t numPhotos, const gpu::BufferRange& table, const gpu::BufferRange& mean);

 private:
  uint32_t dims_, width_;
  gpu::Kernel bias_, gradient_, weightsGradient_, mean_;
  uint32_t maxGroups_;  // of the per-photo sums' dispatch
};

}  // namespace vknerf::nerf

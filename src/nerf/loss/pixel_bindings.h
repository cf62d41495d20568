#pragma once
// The training images on the device: packed RGBA8 (one uint per pixel, R in the low byte) spread
// over as many storage buffers as the device's maxStorageBufferRange requires, each image whole in
// one of them (nerf::PixelPlacement, which nerf::packCameras writes into the cameras), uploaded
// image by image so that no host copy of the whole set is ever made.
#include <cstdint>
#include <span>
#include <vector>

#include "gpu/memory/buffer.h"
#include "nerf/rays/rays.h"
#include "vknerf/context.h"

namespace vknerf::nerf {

// Limits that tests lower to exercise several bindings, or a device too small for a dataset,
// without a dataset of hundreds of megabytes. 0 keeps the device's own. Process-wide.
struct PixelStorageLimits {
  uint64_t bytesPerBinding = 0;  // at most this many bytes of pixels per binding
  uint64_t deviceBytes = 0;      // device memory, instead of the largest device-local heap
};
PixelStorageLimits& pixelStorageLimits();

// Bytes of pixels one binding may hold on this device: maxStorageBufferRange (or the lower
// override), a multiple of 4.
uint64_t pixelBytesPerBinding(const Context& ctx);
// Device memory the whole training run may use: the largest device-local heap, or the override.
uint64_t deviceMemoryBytes(const Context& ctx);

struct PixelLayout {
  std::vector<PixelPlacement> images;   // one per image, in order
  std::vector<uint64_t> bindingPixels;  // pixels each binding holds
  uint64_t totalPixels = 0;
};

// In order, an image joins the last binding when it has room and opens a new binding otherwise.
// Throws vknerf::Error when one image alone is larger than `bytesPerBinding`.
PixelLayout planPixelBindings(std::span<const uint64_t> imagePixels, uint64_t bytesPerBinding);

class TrainingPixels {
 public:
  TrainingPixels(Context& ctx, PixelLayout layout);
  // Copies image `image`'s pixels (imagePixels[image] * 4 bytes, RGBA8) into its place.
  void upload(uint32_t image, const uint8_t* rgba);
  const PixelLayout& layout() const { return layout_; }
  // One range per binding, in binding order.
  std::span<const gpu::BufferRange> bindings() const { return ranges_; }
  uint64_t bytes() const { return layout_.totalPixels * 4; }

 private:
  PixelLayout layout_;
  std::vector<gpu::Buffer> buffers_;
  std::vector<gpu::BufferRange> ranges_;
};

}  // namespace vknerf::nerf

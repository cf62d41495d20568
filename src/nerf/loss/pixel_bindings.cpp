#include "nerf/loss/pixel_bindings.h"

#include <algorithm>
#include <string>

#include "vknerf/error.h"

namespace vknerf::nerf {

PixelStorageLimits& pixelStorageLimits() {
  static PixelStorageLimits limits;
  return limits;
}

uint64_t pixelBytesPerBinding(const Context& ctx) {
  uint64_t bytes = ctx.properties().limits.maxStorageBufferRange;
  if (const uint64_t cap = pixelStorageLimits().bytesPerBinding) bytes = std::min(bytes, cap);
  return bytes / 4 * 4;
}

uint64_t deviceMemoryBytes(const Context& ctx) {
  if (const uint64_t fake = pixelStorageLimits().deviceBytes) return fake;
  VkPhysicalDeviceMemoryProperties mp;
  vkGetPhysicalDeviceMemoryProperties(ctx.physicalDevice(), &mp);
  uint64_t best = 0;
  for (uint32_t h = 0; h < mp.memoryHeapCount; ++h)
    if (mp.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) best = std::max<uint64_t>(best, mp.memoryHeaps[h].size);
  return best;
}

PixelLayout planPixelBindings(std::span<const uint64_t> imagePixels, uint64_t bytesPerBinding) {
  const uint64_t capacity = bytesPerBinding / 4;
  PixelLayout out;
  for (size_t i = 0; i < imagePixels.size(); ++i) {
    const uint64_t n = imagePixels[i];
    if (n > capacity)
      throw Error("training image " + std::to_string(i) + " has " + std::to_string(n) + " pixels, more than one " +
                  "binding of this device holds (" + std::to_string(capacity) + "); raise --downscale");
    if (out.bindingPixels.empty() || out.bindingPixels.back() + n > capacity) out.bindingPixels.push_back(0);
    out.images.push_back({uint32_t(out.bindingPixels.size() - 1), uint32_t(out.bindingPixels.back())});
    out.bindingPixels.back() += n;
    out.totalPixels += n;
  }
  return out;
}

TrainingPixels::TrainingPixels(Context& ctx, PixelLayout layout) : layout_(std::move(layout)) {
  for (uint64_t pixels : layout_.bindingPixels) buffers_.emplace_back(ctx, std::max<uint64_t>(pixels, 1) * 4);
  for (const auto& b : buffers_) ranges_.emplace_back(b);
}

void TrainingPixels::upload(uint32_t image, const uint8_t* rgba) {
  const PixelPlacement at = layout_.images.at(image);
  const uint64_t first = at.firstPixel;
  const uint64_t end = image + 1 < layout_.images.size() && layout_.images[image + 1].binding == at.binding
                           ? layout_.images[image + 1].firstPixel
                           : layout_.bindingPixels[at.binding];
  buffers_[at.binding].upload(rgba, (end - first) * 4, first * 4);
}

}  // namespace vknerf::nerf

#pragma once
// Where Model::recordRender writes: a caller's VkBuffer or a caller's storage image.
#include <vulkan/vulkan.h>

#include <cstdint>

namespace vknerf {

enum class RenderChannel : uint32_t {
  Color = 0,  // rgb composited over the model's background, a = opacity
  Depth = 1,  // expected depth (sum w_i t_i / opacity, 0 where nothing was hit) as grey, scaled by depthScale
};

struct RenderTarget {
  uint32_t width = 0, height = 0;  // must equal the camera's image size
  RenderChannel channel = RenderChannel::Color;
  float depthScale = 1.0f;  // Depth channel: written value = depth * depthScale (clamped to [0, 1] for UNORM)

  // Either a buffer: width * height RGBA32F texels (16 bytes each), row-major, top row first, at
  // `offset` (a multiple of the device's minStorageBufferOffsetAlignment), created with
  // VK_BUFFER_USAGE_STORAGE_BUFFER_BIT ...
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize offset = 0;
  // ... or a 2D storage image view (VK_IMAGE_USAGE_STORAGE_BIT, format VK_FORMAT_R8G8B8A8_UNORM or
  // VK_FORMAT_R32G32B32A32_SFLOAT), in VK_IMAGE_LAYOUT_GENERAL while the commands execute.
  VkImageView imageView = VK_NULL_HANDLE;
  VkFormat imageFormat = VK_FORMAT_UNDEFINED;
};

}  // namespace vknerf

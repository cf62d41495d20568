#pragma once
// The embedding application's side of the Vulkan API, as the embedding tests play it: buffers,
// storage images, a command buffer and the barriers that the recordRender contract asks of the
// caller, all created with plain Vulkan on the application's device (vknerf's context's handles,
// or an instance and device of the application's own: app_device.h).
#include <vulkan/vulkan.h>

#include <vector>

#include "vknerf/context.h"

namespace vknerf::test {

// The application's device handles.
struct AppDevice {
  VkPhysicalDevice phys;
  VkDevice dev;
  VkQueue queue;
  uint32_t family;
  static AppDevice of(const Context& c) { return {c.physicalDevice(), c.device(), c.queue(), c.queueFamily()}; }
};

// A host-visible buffer the application owns (storage target and readback), mapped.
struct AppBuffer {
  AppDevice d;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;
  VkDeviceSize size;
  AppBuffer(AppDevice dev, VkDeviceSize bytes);
  ~AppBuffer();
  AppBuffer(const AppBuffer&) = delete;
  AppBuffer& operator=(const AppBuffer&) = delete;
  std::vector<float> floats(VkDeviceSize offset, size_t count) const;
};

// A 2D storage image the application owns (read back by copying it into a buffer).
struct AppImage {
  AppDevice d;
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  AppImage(AppDevice dev, uint32_t w, uint32_t h, VkFormat format);
  ~AppImage();
  AppImage(const AppImage&) = delete;
  AppImage& operator=(const AppImage&) = delete;
};

// The application's command pool, one primary command buffer, and a fence.
struct AppCommands {
  AppDevice d;
  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  explicit AppCommands(AppDevice dev);
  ~AppCommands();
  AppCommands(const AppCommands&) = delete;
  AppCommands& operator=(const AppCommands&) = delete;
  void begin();          // reset and begin, one-time submit
  void submitAndWait();  // end, submit and wait on the fence
};

// The contract's barriers, as the application records them.
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags srcAccess, VkPipelineStageFlags dst,
                   VkAccessFlags dstAccess);
// Before: a sentinel fill (so an unwritten texel shows) made visible to the render's shader writes.
void fillBeforeRender(VkCommandBuffer cmd, const AppBuffer& b, float sentinel);
// After: the render's writes made visible to the host (a mapped buffer read after the fence).
void renderToHost(VkCommandBuffer cmd);
void imageLayout(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to, VkPipelineStageFlags src,
                 VkAccessFlags srcAccess, VkPipelineStageFlags dst, VkAccessFlags dstAccess);

}  // namespace vknerf::test

#pragma once
// Small Vulkan helpers for the viewer. The viewer is an external application of vknerf: it sees only
// <vknerf/...>, so it carries its own result check rather than the library's private one.
#include <vulkan/vulkan.h>

#include <string>

#include "vknerf/error.h"

namespace viewer {

inline const char* resultName(VkResult r) {
  switch (r) {
#define VIEWER_CASE(x) case x: return #x;
    VIEWER_CASE(VK_NOT_READY) VIEWER_CASE(VK_TIMEOUT) VIEWER_CASE(VK_INCOMPLETE) VIEWER_CASE(VK_SUBOPTIMAL_KHR)
    VIEWER_CASE(VK_ERROR_OUT_OF_HOST_MEMORY) VIEWER_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    VIEWER_CASE(VK_ERROR_INITIALIZATION_FAILED) VIEWER_CASE(VK_ERROR_DEVICE_LOST)
    VIEWER_CASE(VK_ERROR_LAYER_NOT_PRESENT) VIEWER_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    VIEWER_CASE(VK_ERROR_FEATURE_NOT_PRESENT) VIEWER_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    VIEWER_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED) VIEWER_CASE(VK_ERROR_SURFACE_LOST_KHR)
    VIEWER_CASE(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR) VIEWER_CASE(VK_ERROR_OUT_OF_DATE_KHR)
#undef VIEWER_CASE
    default: return "VkResult error";
  }
}

// Throws vknerf::Error naming the call and its result (one line, like the library's errors).
inline void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw vknerf::Error(std::string(what) + " failed: " + resultName(r));
}

// Image layout transition / memory dependency on one colour image (all of it).
inline void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                         VkPipelineStageFlags srcStage, VkAccessFlags srcAccess, VkPipelineStageFlags dstStage,
                         VkAccessFlags dstAccess) {
  VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  b.srcAccessMask = srcAccess;
  b.dstAccessMask = dstAccess;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

}  // namespace viewer

#pragma once
// The window's swapchain: images the viewer blits into (TRANSFER_DST), recreated when the window
// changes size. Prefers a UNORM format: vknerf's colours are already sRGB-encoded, so an _SRGB
// swapchain would encode them twice.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <vector>

#include "window_device.h"

namespace viewer {

class Swapchain {
 public:
  explicit Swapchain(const WindowDevice& wd);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  // (Re)creates for the window's current framebuffer size; false while the window is minimised.
  bool recreate();
  VkSwapchainKHR handle() const { return swapchain_; }
  VkFormat format() const { return format_; }
  VkExtent2D extent() const { return extent_; }
  const std::vector<VkImage>& images() const { return images_; }
  // One per image: signalled by the frame that draws the image, waited on by its present.
  VkSemaphore renderDone(uint32_t image) const { return renderDone_[image]; }

 private:
  void destroyPerImage();

  const WindowDevice& wd_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkExtent2D extent_{0, 0};
  std::vector<VkImage> images_;
  std::vector<VkSemaphore> renderDone_;
};

}  // namespace viewer

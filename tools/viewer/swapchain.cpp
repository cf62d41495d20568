#include "swapchain.h"

#include <algorithm>

#include "vk_util.h"

namespace viewer {
namespace {

VkSurfaceFormatKHR chooseFormat(VkPhysicalDevice pd, VkSurfaceKHR surface) {
  uint32_t n = 0;
  vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr);
  std::vector<VkSurfaceFormatKHR> formats(n);
  vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, formats.data());
  if (formats.empty()) throw vknerf::Error("the window surface offers no formats");
  for (VkFormat want : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_A8B8G8R8_UNORM_PACK32})
    for (auto& f : formats)
      if (f.format == want) return f;
  return formats[0];
}

VkPresentModeKHR choosePresentMode(VkPhysicalDevice pd, VkSurfaceKHR surface) {
  uint32_t n = 0;
  vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, nullptr);
  std::vector<VkPresentModeKHR> modes(n);
  vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, modes.data());
  // Mailbox never blocks on vertical blank (a frame costs far more than a refresh here); FIFO always exists.
  return std::find(modes.begin(), modes.end(), VK_PRESENT_MODE_MAILBOX_KHR) != modes.end() ? VK_PRESENT_MODE_MAILBOX_KHR
                                                                                        : VK_PRESENT_MODE_FIFO_KHR;
}

}  // namespace

Swapchain::Swapchain(const WindowDevice& wd) : wd_(wd) {}

Swapchain::~Swapchain() {
  destroyPerImage();
  if (swapchain_) vkDestroySwapchainKHR(wd_.device(), swapchain_, nullptr);
}

void Swapchain::destroyPerImage() {
  for (VkSemaphore s : renderDone_) vkDestroySemaphore(wd_.device(), s, nullptr);
  renderDone_.clear();
  images_.clear();
}

bool Swapchain::recreate() {
  VkSurfaceCapabilitiesKHR caps;
  check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(wd_.physicalDevice(), wd_.surface(), &caps),
        "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
  VkExtent2D extent = caps.currentExtent;
  if (extent.width == UINT32_MAX) {  // the surface takes the swapchain's size: use the framebuffer's
    int w = 0, h = 0;
    glfwGetFramebufferSize(wd_.window(), &w, &h);
    extent.width = std::clamp(uint32_t(std::max(w, 0)), caps.minImageExtent.width, caps.maxImageExtent.width);
    extent.height = std::clamp(uint32_t(std::max(h, 0)), caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  if (extent.width == 0 || extent.height == 0) return false;
  if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
    throw vknerf::Error("the window surface's images cannot be transfer destinations (needed to blit the render into them)");

  const VkSurfaceFormatKHR format = chooseFormat(wd_.physicalDevice(), wd_.surface());
  VkFormatProperties fp;
  vkGetPhysicalDeviceFormatProperties(wd_.physicalDevice(), format.format, &fp);
  if (!(fp.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_DST_BIT))
    throw vknerf::Error("swapchain format " + std::to_string(format.format) + " cannot be a blit destination");

  uint32_t count = caps.minImageCount + 1;
  if (caps.maxImageCount) count = std::min(count, caps.maxImageCount);
  VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  ci.surface = wd_.surface();
  ci.minImageCount = count;
  ci.imageFormat = format.format;
  ci.imageColorSpace = format.colorSpace;
  ci.imageExtent = extent;
  ci.imageArrayLayers = 1;
  ci.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  ci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ci.preTransform = (caps.supportedTransforms & VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR) ? VK_SURFACE_TRANSFORM_IDENTITY_BIT_KHR
                                                                                       : caps.currentTransform;
  ci.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  for (auto a : {VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR, VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR, VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR,
                 VK_COMPOSITE_ALPHA_POST_MULTIPLIED_BIT_KHR})
    if (caps.supportedCompositeAlpha & a) {
      ci.compositeAlpha = a;
      break;
    }
  ci.presentMode = choosePresentMode(wd_.physicalDevice(), wd_.surface());
  ci.clipped = VK_TRUE;
  ci.oldSwapchain = swapchain_;
  VkSwapchainKHR created = VK_NULL_HANDLE;
  check(vkCreateSwapchainKHR(wd_.device(), &ci, nullptr, &created), "vkCreateSwapchainKHR");
  // The caller has waited for the device to be idle, so the old chain's images are no longer in use.
  destroyPerImage();
  if (swapchain_) vkDestroySwapchainKHR(wd_.device(), swapchain_, nullptr);
  swapchain_ = created;
  format_ = format.format;
  extent_ = extent;

  uint32_t n = 0;
  vkGetSwapchainImagesKHR(wd_.device(), swapchain_, &n, nullptr);
  images_.resize(n);
  vkGetSwapchainImagesKHR(wd_.device(), swapchain_, &n, images_.data());
  renderDone_.resize(n, VK_NULL_HANDLE);
  for (auto& s : renderDone_) {
    VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    check(vkCreateSemaphore(wd_.device(), &si, nullptr, &s), "vkCreateSemaphore");
  }
  return true;
}

}  // namespace viewer

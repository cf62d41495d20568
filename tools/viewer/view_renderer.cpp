#include "view_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#define STB_IMAGE_WRITE_STATIC  // vknerf holds its own copy of stb; keep ours private to this file
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include "vk_util.h"
#include "vknerf/file_output.h"

namespace viewer {
namespace {

constexpr VkFormat kTargetFormat = VK_FORMAT_R8G8B8A8_UNORM;

uint32_t memoryType(VkPhysicalDevice pd, uint32_t typeBits, VkMemoryPropertyFlags want, VkMemoryPropertyFlags fallback) {
  VkPhysicalDeviceMemoryProperties props;
  vkGetPhysicalDeviceMemoryProperties(pd, &props);
  for (VkMemoryPropertyFlags flags : {want, fallback})
    for (uint32_t i = 0; i < props.memoryTypeCount; ++i)
      if ((typeBits & (1u << i)) && (props.memoryTypes[i].propertyFlags & flags) == flags) return i;
  throw vknerf::Error("no Vulkan memory type with properties " + std::to_string(fallback));
}

}  // namespace

ViewRenderer::ViewRenderer(const WindowDevice& wd, uint32_t width, uint32_t height, uint32_t lowFactor) : wd_(wd) {
  VkFormatProperties fp;
  vkGetPhysicalDeviceFormatProperties(wd.physicalDevice(), kTargetFormat, &fp);
  const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT | VK_FORMAT_FEATURE_BLIT_SRC_BIT;
  if ((fp.optimalTilingFeatures & need) != need)
    throw vknerf::Error(wd.deviceName() + ": R8G8B8A8_UNORM images cannot be both storage images and blit sources");
  // Linear filtering smooths the 4x upscale of the low-resolution image; nearest where unsupported.
  if (fp.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT) filter_ = VK_FILTER_LINEAR;

  VkDevice dev = wd.device();
  VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pi.queueFamilyIndex = wd.queueFamily();
  check(vkCreateCommandPool(dev, &pi, nullptr, &pool_), "vkCreateCommandPool");
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool_;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(dev, &ai, &cmd_), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  check(vkCreateFence(dev, &fi, nullptr, &fence_), "vkCreateFence");
  VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  check(vkCreateSemaphore(dev, &si, nullptr, &acquired_), "vkCreateSemaphore");

  createTarget(full_, width, height);
  createTarget(low_, (width + lowFactor - 1) / lowFactor, (height + lowFactor - 1) / lowFactor);

  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = VkDeviceSize(width) * height * 4;
  bi.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  check(vkCreateBuffer(dev, &bi, nullptr, &staging_), "vkCreateBuffer");
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(dev, staging_, &req);
  VkMemoryAllocateInfo mi{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mi.allocationSize = req.size;
  const VkMemoryPropertyFlags hostFlags = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  mi.memoryTypeIndex = memoryType(wd.physicalDevice(), req.memoryTypeBits, hostFlags, hostFlags);
  check(vkAllocateMemory(dev, &mi, nullptr, &stagingMemory_), "vkAllocateMemory");
  check(vkBindBufferMemory(dev, staging_, stagingMemory_, 0), "vkBindBufferMemory");
  check(vkMapMemory(dev, stagingMemory_, 0, VK_WHOLE_SIZE, 0, &stagingMapped_), "vkMapMemory");

  // Black until the first render, so a frame shown before it has defined contents.
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd_, &begin), "vkBeginCommandBuffer");
  for (Target* t : {&full_, &low_}) {
    transition(cmd_, *t, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
               VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    VkClearColorValue black{};
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd_, t->image, t->layout, &black, 1, &range);
    transition(cmd_, *t, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
               VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  }
  check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
  submitAndWait(cmd_);
  shown_ = &full_;
}

ViewRenderer::~ViewRenderer() {
  VkDevice dev = wd_.device();
  vkDeviceWaitIdle(dev);
  destroyTarget(full_);
  destroyTarget(low_);
  if (staging_) vkDestroyBuffer(dev, staging_, nullptr);
  if (stagingMemory_) vkFreeMemory(dev, stagingMemory_, nullptr);
  if (acquired_) vkDestroySemaphore(dev, acquired_, nullptr);
  if (fence_) vkDestroyFence(dev, fence_, nullptr);
  if (pool_) vkDestroyCommandPool(dev, pool_, nullptr);
}

void ViewRenderer::createTarget(Target& t, uint32_t width, uint32_t height) {
  VkDevice dev = wd_.device();
  t.width = width;
  t.height = height;
  VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ii.imageType = VK_IMAGE_TYPE_2D;
  ii.format = kTargetFormat;
  ii.extent = {width, height, 1};
  ii.mipLevels = 1;
  ii.arrayLayers = 1;
  ii.samples = VK_SAMPLE_COUNT_1_BIT;
  ii.tiling = VK_IMAGE_TILING_OPTIMAL;
  ii.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  ii.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  check(vkCreateImage(dev, &ii, nullptr, &t.image), "vkCreateImage");
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(dev, t.image, &req);
  VkMemoryAllocateInfo mi{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mi.allocationSize = req.size;
  mi.memoryTypeIndex = memoryType(wd_.physicalDevice(), req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0);
  check(vkAllocateMemory(dev, &mi, nullptr, &t.memory), "vkAllocateMemory");
  check(vkBindImageMemory(dev, t.image, t.memory, 0), "vkBindImageMemory");
  VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vi.image = t.image;
  vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vi.format = kTargetFormat;
  vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  check(vkCreateImageView(dev, &vi, nullptr, &t.view), "vkCreateImageView");
}

void ViewRenderer::destroyTarget(Target& t) {
  VkDevice dev = wd_.device();
  if (t.view) vkDestroyImageView(dev, t.view, nullptr);
  if (t.image) vkDestroyImage(dev, t.image, nullptr);
  if (t.memory) vkFreeMemory(dev, t.memory, nullptr);
  t = Target{};
}

void ViewRenderer::transition(VkCommandBuffer cmd, Target& t, VkImageLayout layout, VkPipelineStageFlags srcStage,
                              VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
  imageBarrier(cmd, t.image, t.layout, layout, srcStage, srcAccess, dstStage, dstAccess);
  t.layout = layout;
}

void ViewRenderer::submitAndWait(VkCommandBuffer cmd) {
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  check(vkQueueSubmit(wd_.queue(), 1, &si, fence_), "vkQueueSubmit");
  check(vkWaitForFences(wd_.device(), 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  check(vkResetFences(wd_.device(), 1, &fence_), "vkResetFences");
}

void ViewRenderer::recordRender(VkCommandBuffer cmd, const RenderRequest& request, Target& target) {
  if (request.camera.width != target.width || request.camera.height != target.height)
    throw vknerf::Error("viewer: camera " + std::to_string(request.camera.width) + "x" + std::to_string(request.camera.height) +
                        " does not match its render target " + std::to_string(target.width) + "x" + std::to_string(target.height));
  // vknerf's own buffers (scratch, parameters a training step updated) are synchronised by the
  // barrier its recording begins with; the target is ours to hand over.
  // The target: the last frame's blit read it (write-after-read), then vknerf writes it as storage.
  transition(cmd, target, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
             VK_ACCESS_SHADER_WRITE_BIT);
  vknerf::RenderTarget rt;
  rt.width = target.width;
  rt.height = target.height;
  rt.channel = request.channel;
  rt.depthScale = request.depthScale;
  rt.imageView = target.view;
  rt.imageFormat = kTargetFormat;
  request.model->recordRender(cmd, request.camera, rt);
  // vknerf's writes, to the blit (and a screenshot's copy).
  transition(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
             VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
}

void ViewRenderer::recordBlit(VkCommandBuffer cmd, VkImage swapImage, VkExtent2D extent) {
  // The swapchain image's old contents are not needed: UNDEFINED -> TRANSFER_DST. The acquire
  // semaphore is waited on at the transfer stage, which this barrier's first scope chains to.
  imageBarrier(cmd, swapImage, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
               0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
  VkClearColorValue black{};
  VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdClearColorImage(cmd, swapImage, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &black, 1, &range);
  imageBarrier(cmd, swapImage, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
               VK_ACCESS_TRANSFER_WRITE_BIT);

  // Letterbox: the largest rectangle of the full image's aspect ratio that fits the window, centred.
  // The low-resolution image fills the same rectangle (the blit upscales it).
  const double scale = std::min(double(extent.width) / full_.width, double(extent.height) / full_.height);
  const int32_t w = std::max(1, int32_t(std::lround(full_.width * scale)));
  const int32_t h = std::max(1, int32_t(std::lround(full_.height * scale)));
  const int32_t x0 = (int32_t(extent.width) - w) / 2, y0 = (int32_t(extent.height) - h) / 2;
  VkImageBlit blit{};
  blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.srcOffsets[1] = {int32_t(shown_->width), int32_t(shown_->height), 1};
  blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.dstOffsets[0] = {x0, y0, 0};
  blit.dstOffsets[1] = {x0 + w, y0 + h, 1};
  vkCmdBlitImage(cmd, shown_->image, shown_->layout, swapImage, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, filter_);

  imageBarrier(cmd, swapImage, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
               VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0);
}

FrameStatus ViewRenderer::drawFrame(Swapchain& swapchain, const RenderRequest* request) {
  VkDevice dev = wd_.device();
  uint32_t index = 0;
  VkResult r = vkAcquireNextImageKHR(dev, swapchain.handle(), UINT64_MAX, acquired_, VK_NULL_HANDLE, &index);
  if (r == VK_ERROR_OUT_OF_DATE_KHR) return FrameStatus::OutOfDate;
  if (r != VK_SUBOPTIMAL_KHR) check(r, "vkAcquireNextImageKHR");
  bool stale = r == VK_SUBOPTIMAL_KHR;

  check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd_, &begin), "vkBeginCommandBuffer");
  if (request) {
    Target& target = request->low ? low_ : full_;
    recordRender(cmd_, *request, target);
    shown_ = &target;
  }
  recordBlit(cmd_, swapchain.images()[index], swapchain.extent());
  check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");

  const VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_TRANSFER_BIT;
  const VkSemaphore done = swapchain.renderDone(index);
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.waitSemaphoreCount = 1;
  si.pWaitSemaphores = &acquired_;
  si.pWaitDstStageMask = &waitStage;
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd_;
  si.signalSemaphoreCount = 1;
  si.pSignalSemaphores = &done;
  check(vkQueueSubmit(wd_.queue(), 1, &si, fence_), "vkQueueSubmit");

  VkSwapchainKHR handle = swapchain.handle();
  VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  pi.waitSemaphoreCount = 1;
  pi.pWaitSemaphores = &done;
  pi.swapchainCount = 1;
  pi.pSwapchains = &handle;
  pi.pImageIndices = &index;
  r = vkQueuePresentKHR(wd_.queue(), &pi);
  if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR)
    stale = true;
  else
    check(r, "vkQueuePresentKHR");
  // One frame in flight: the next recording reuses this command buffer and the model's scratch.
  check(vkWaitForFences(dev, 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  check(vkResetFences(dev, 1, &fence_), "vkResetFences");
  return stale ? FrameStatus::PresentedStale : FrameStatus::Presented;
}

void ViewRenderer::saveScreenshot(const std::string& path) {
  const Target& t = *shown_;
  check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd_, &begin), "vkBeginCommandBuffer");
  // The shown image is already TRANSFER_SRC_OPTIMAL with the render's writes visible to transfers.
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {t.width, t.height, 1};
  vkCmdCopyImageToBuffer(cmd_, t.image, t.layout, staging_, 1, &region);
  VkBufferMemoryBarrier bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
  bb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  bb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  bb.srcQueueFamilyIndex = bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  bb.buffer = staging_;
  bb.size = VK_WHOLE_SIZE;
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1, &bb, 0, nullptr);
  check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
  submitAndWait(cmd_);

  // RGB only: alpha holds the opacity, which the window does not show.
  const auto* rgba = static_cast<const uint8_t*>(stagingMapped_);
  std::vector<uint8_t> rgb(size_t(t.width) * t.height * 3);
  for (size_t p = 0; p < size_t(t.width) * t.height; ++p) std::memcpy(&rgb[p * 3], &rgba[p * 4], 3);
  // Encoded in memory, then written atomically: a full disk is an error, not a 0-byte screenshot.
  std::vector<uint8_t> png;
  const auto append = [](void* out, void* data, int size) {
    auto* bytes = static_cast<std::vector<uint8_t>*>(out);
    bytes->insert(bytes->end(), static_cast<uint8_t*>(data), static_cast<uint8_t*>(data) + size);
  };
  if (!stbi_write_png_to_func(append, &png, int(t.width), int(t.height), 3, rgb.data(), int(t.width) * 3))
    throw vknerf::Error(path + ": cannot encode the screenshot PNG");
  vknerf::writeFileAtomically(path, png.data(), png.size());
}

}  // namespace viewer

#include "support/app_vulkan.h"

#include <gtest/gtest.h>

#include <cstring>

namespace vknerf::test {
namespace {

uint32_t memoryType(VkPhysicalDevice phys, uint32_t bits, VkMemoryPropertyFlags want) {
  VkPhysicalDeviceMemoryProperties mp;
  vkGetPhysicalDeviceMemoryProperties(phys, &mp);
  for (uint32_t i = 0; i < mp.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want) return i;
  ADD_FAILURE() << "no memory type";
  return 0;
}

}  // namespace

AppBuffer::AppBuffer(AppDevice dev, VkDeviceSize bytes) : d(dev), size(bytes) {
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = bytes;
  bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  EXPECT_EQ(vkCreateBuffer(d.dev, &bi, nullptr, &buffer), VK_SUCCESS);
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(d.dev, buffer, &req);
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = memoryType(d.phys, req.memoryTypeBits,
                                  VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  EXPECT_EQ(vkAllocateMemory(d.dev, &ai, nullptr, &memory), VK_SUCCESS);
  EXPECT_EQ(vkBindBufferMemory(d.dev, buffer, memory, 0), VK_SUCCESS);
  EXPECT_EQ(vkMapMemory(d.dev, memory, 0, VK_WHOLE_SIZE, 0, &mapped), VK_SUCCESS);
}

AppBuffer::~AppBuffer() {
  vkDestroyBuffer(d.dev, buffer, nullptr);
  vkFreeMemory(d.dev, memory, nullptr);
}

std::vector<float> AppBuffer::floats(VkDeviceSize offset, size_t count) const {
  std::vector<float> v(count);
  std::memcpy(v.data(), static_cast<const char*>(mapped) + offset, count * sizeof(float));
  return v;
}

AppImage::AppImage(AppDevice dev, uint32_t w, uint32_t h, VkFormat format) : d(dev) {
  VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ii.imageType = VK_IMAGE_TYPE_2D;
  ii.format = format;
  ii.extent = {w, h, 1};
  ii.mipLevels = ii.arrayLayers = 1;
  ii.samples = VK_SAMPLE_COUNT_1_BIT;
  ii.tiling = VK_IMAGE_TILING_OPTIMAL;
  ii.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  EXPECT_EQ(vkCreateImage(d.dev, &ii, nullptr, &image), VK_SUCCESS);
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(d.dev, image, &req);
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = memoryType(d.phys, req.memoryTypeBits, 0);
  EXPECT_EQ(vkAllocateMemory(d.dev, &ai, nullptr, &memory), VK_SUCCESS);
  EXPECT_EQ(vkBindImageMemory(d.dev, image, memory, 0), VK_SUCCESS);
  VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vi.image = image;
  vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vi.format = format;
  vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  EXPECT_EQ(vkCreateImageView(d.dev, &vi, nullptr, &view), VK_SUCCESS);
}

AppImage::~AppImage() {
  vkDestroyImageView(d.dev, view, nullptr);
  vkDestroyImage(d.dev, image, nullptr);
  vkFreeMemory(d.dev, memory, nullptr);
}

AppCommands::AppCommands(AppDevice dev) : d(dev) {
  VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pi.queueFamilyIndex = d.family;
  EXPECT_EQ(vkCreateCommandPool(d.dev, &pi, nullptr, &pool), VK_SUCCESS);
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  EXPECT_EQ(vkAllocateCommandBuffers(d.dev, &ai, &cmd), VK_SUCCESS);
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  EXPECT_EQ(vkCreateFence(d.dev, &fi, nullptr, &fence), VK_SUCCESS);
}

AppCommands::~AppCommands() {
  vkDestroyFence(d.dev, fence, nullptr);
  vkDestroyCommandPool(d.dev, pool, nullptr);
}

void AppCommands::begin() {
  ASSERT_EQ(vkResetCommandBuffer(cmd, 0), VK_SUCCESS);
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  ASSERT_EQ(vkBeginCommandBuffer(cmd, &bi), VK_SUCCESS);
}

void AppCommands::submitAndWait() {
  ASSERT_EQ(vkEndCommandBuffer(cmd), VK_SUCCESS);
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  ASSERT_EQ(vkResetFences(d.dev, 1, &fence), VK_SUCCESS);
  ASSERT_EQ(vkQueueSubmit(d.queue, 1, &si, fence), VK_SUCCESS);
  ASSERT_EQ(vkWaitForFences(d.dev, 1, &fence, VK_TRUE, UINT64_MAX), VK_SUCCESS);
}

void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags srcAccess, VkPipelineStageFlags dst,
                   VkAccessFlags dstAccess) {
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = srcAccess;
  mb.dstAccessMask = dstAccess;
  vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

void fillBeforeRender(VkCommandBuffer cmd, const AppBuffer& b, float sentinel) {
  uint32_t bits;
  std::memcpy(&bits, &sentinel, 4);
  vkCmdFillBuffer(cmd, b.buffer, 0, VK_WHOLE_SIZE, bits);
  memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                VK_ACCESS_SHADER_WRITE_BIT);
}

void renderToHost(VkCommandBuffer cmd) {
  memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                VK_ACCESS_HOST_READ_BIT);
}

void imageLayout(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to, VkPipelineStageFlags src,
                 VkAccessFlags srcAccess, VkPipelineStageFlags dst, VkAccessFlags dstAccess) {
  VkImageMemoryBarrier ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  ib.srcAccessMask = srcAccess;
  ib.dstAccessMask = dstAccess;
  ib.oldLayout = from;
  ib.newLayout = to;
  ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  ib.image = image;
  ib.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cmd, src, dst, 0, 0, nullptr, 0, nullptr, 1, &ib);
}

}  // namespace vknerf::test

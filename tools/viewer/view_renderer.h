#pragma once
// Per-frame GPU work of the viewer, in one command buffer per frame:
//   [optional] vknerf renders the camera into a storage image (R8G8B8A8_UNORM, layout GENERAL),
//              full resolution or 1/lowFactor of it while the camera moves;
//   the most recently rendered image is blitted (scaled, format-converted, letterboxed) into the
//   acquired swapchain image, which is then presented.
// One frame is in flight at a time: vknerf reuses a model's scratch buffers for every recording.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>

#include "swapchain.h"
#include "vknerf/camera.h"
#include "vknerf/render_target.h"
#include "vknerf/trainer.h"
#include "window_device.h"

namespace viewer {

struct RenderRequest {
  const vknerf::Model* model = nullptr;
  vknerf::Camera camera;  // at full resolution, or at 1/lowFactor of it when `low`
  bool low = false;
  vknerf::RenderChannel channel = vknerf::RenderChannel::Color;
  float depthScale = 1.0f;
};

enum class FrameStatus {
  Presented,       // drawn and presented
  PresentedStale,  // drawn and presented, but the swapchain no longer matches the window: recreate it
  OutOfDate,       // nothing done: recreate the swapchain and draw again
};

class ViewRenderer {
 public:
  // width x height: the camera's (full) resolution, the size of the screenshot.
  ViewRenderer(const WindowDevice& wd, uint32_t width, uint32_t height, uint32_t lowFactor);
  ~ViewRenderer();
  ViewRenderer(const ViewRenderer&) = delete;
  ViewRenderer& operator=(const ViewRenderer&) = delete;

  // Renders `request` (if given) and shows the latest image; waits until the frame has executed.
  FrameStatus drawFrame(Swapchain& swapchain, const RenderRequest* request);
  // Writes the image shown by the last frame (its RGB) as PNG; throws vknerf::Error.
  void saveScreenshot(const std::string& path);
  bool showingLowResolution() const { return shown_ == &low_; }

 private:
  struct Target {
    uint32_t width = 0, height = 0;
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    // GENERAL while vknerf writes it, TRANSFER_SRC_OPTIMAL while it is shown (blits, screenshot).
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  };
  // Moves `t` to `layout` with the given memory dependency (same-layout: just the dependency).
  static void transition(VkCommandBuffer cmd, Target& t, VkImageLayout layout, VkPipelineStageFlags srcStage,
                         VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);
  void createTarget(Target& t, uint32_t width, uint32_t height);
  void destroyTarget(Target& t);
  void recordRender(VkCommandBuffer cmd, const RenderRequest& request, Target& target);
  void recordBlit(VkCommandBuffer cmd, VkImage swapImage, VkExtent2D extent);
  void submitAndWait(VkCommandBuffer cmd);

  const WindowDevice& wd_;
  Target full_, low_;
  const Target* shown_ = nullptr;  // what the last frame put on screen
  VkFilter filter_ = VK_FILTER_NEAREST;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkSemaphore acquired_ = VK_NULL_HANDLE;
  // Host-visible RGBA8 buffer of the full image: the screenshot's readback.
  VkBuffer staging_ = VK_NULL_HANDLE;
  VkDeviceMemory stagingMemory_ = VK_NULL_HANDLE;
  void* stagingMapped_ = nullptr;
};

}  // namespace viewer

#include "nerf/render/render_target_writer.h"

#include <cmath>
#include <cstdint>
#include <string>

#include "vknerf/error.h"
#include "render/write_render_target_shared.h"

namespace vknerf::nerf {
namespace {

constexpr uint32_t kLocal = 64;  // shaders/render/write_render_target.comp
constexpr VkDeviceSize kTexelBytes = 16;

using Push = glsl::RenderTargetPush;

std::string sizeText(uint32_t w, uint32_t h) { return std::to_string(w) + "x" + std::to_string(h); }

}  // namespace

void checkRenderTarget(const Context& ctx, const Camera& cam, const RenderTarget& t) {
  const std::string where = "recordRender: ";
  if (cam.width == 0 || cam.height == 0) throw Error(where + "camera has an empty image size");
  if (!(cam.fx > 0) || !(cam.fy > 0)) throw Error(where + "camera focal length must be positive");
  if (uint64_t(cam.width) * cam.height > UINT32_MAX) throw Error(where + "camera image has over 2^32 pixels");
  if (t.width != cam.width || t.height != cam.height)
    throw Error(where + "target width/height " + sizeText(t.width, t.height) + " differ from the camera's image " +
                sizeText(cam.width, cam.height));
  if (t.channel != RenderChannel::Color && t.channel != RenderChannel::Depth)
    throw Error(where + "target channel " + std::to_string(uint32_t(t.channel)) + " is neither Color nor Depth");
  if (t.channel == RenderChannel::Depth && !std::isfinite(t.depthScale))
    throw Error(where + "target depthScale is not finite");
  const bool hasBuffer = t.buffer != VK_NULL_HANDLE, hasImage = t.imageView != VK_NULL_HANDLE;
  if (hasBuffer == hasImage)
    throw Error(where + (hasBuffer ? "target sets both buffer and imageView; set exactly one"
                                   : "target sets neither buffer nor imageView; set exactly one"));
  const auto& limits = ctx.properties().limits;
  if (hasBuffer) {
    if (t.offset % limits.minStorageBufferOffsetAlignment)
      throw Error(where + "target offset " + std::to_string(t.offset) + " is not a multiple of the device's "
                  "minStorageBufferOffsetAlignment " + std::to_string(limits.minStorageBufferOffsetAlignment));
    const VkDeviceSize bytes = VkDeviceSize(t.width) * t.height * kTexelBytes;
    if (bytes > limits.maxStorageBufferRange)
      throw Error(where + "target buffer of " + sizeText(t.width, t.height) + " RGBA32F texels spans " +
                  std::to_string(bytes) + " bytes, over the device's maxStorageBufferRange " +
                  std::to_string(limits.maxStorageBufferRange) + "; render into an image");
  } else if (t.imageFormat != VK_FORMAT_R8G8B8A8_UNORM && t.imageFormat != VK_FORMAT_R32G32B32A32_SFLOAT) {
    throw Error(where + "target imageFormat " + std::to_string(int(t.imageFormat)) +
                " is not supported (VK_FORMAT_R8G8B8A8_UNORM or VK_FORMAT_R32G32B32A32_SFLOAT)");
  }
}

RenderTargetWriter::RenderTargetWriter(Context& ctx) : ctx_(ctx) {}
RenderTargetWriter::~RenderTargetWriter() = default;

gpu::Kernel& RenderTargetWriter::kernelFor(const RenderTarget& t) {
  using gpu::Binding;
  auto make = [&](std::unique_ptr<gpu::Kernel>& k, const gpu::ShaderCode& shader, Binding target) -> gpu::Kernel& {
    if (!k)
      k = std::make_unique<gpu::Kernel>(
          ctx_, gpu::KernelDesc{shader, {Binding::Storage, Binding::Storage, target}, sizeof(Push), {}});
    return *k;
  };
  if (t.buffer) return make(buffer_, gpu::shaders::write_render_target, Binding::Storage);
  if (t.imageFormat == VK_FORMAT_R8G8B8A8_UNORM) return make(rgba8_, gpu::shaders::write_render_target_rgba8, Binding::StorageImage);
  return make(rgba32f_, gpu::shaders::write_render_target_rgba32f, Binding::StorageImage);
}

RenderTargetWriter::Bound RenderTargetWriter::bind(const RenderTarget& t, const gpu::Buffer& color,
                                                   const gpu::Buffer& depth) {
  gpu::Kernel& k = kernelFor(t);
  const gpu::BufferRange target =
      t.buffer ? gpu::BufferRange::externalBuffer(t.buffer, t.offset, VkDeviceSize(t.width) * t.height * kTexelBytes)
               : gpu::BufferRange::storageImage(t.imageView);
  const gpu::BufferRange bindings[] = {color, depth, target};
  return {&k, k.transientSet(bindings), t.width, t.channel, t.depthScale};
}

void RenderTargetWriter::record(gpu::Recorder& rec, const Bound& b, uint32_t first, uint32_t count) {
  const Push push{first, count, b.width, uint32_t(b.channel), b.depthScale};
  rec.dispatchWithSet(*b.kernel, b.set, &push, sizeof push, gpu::groupsFor(count, kLocal), 1, 1, "write render target");
}

}  // namespace vknerf::nerf

// The synchronization a GPU needs: the suite runs under the validation layer's synchronization
// validation (CMakeLists.txt: VK_LAYER_ENABLES), which lavapipe's serial execution would otherwise
// hide. This test proves it is on: a dispatch writing a buffer and a fill of it with no barrier
// between them are a write-after-write hazard the layer reports, and the Recorder's barrier
// removes it. (Debian's 1.3.239 layer does not report the same hazard between two dispatches.)
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "nerf/rays/rays.h"
#include "rays/rays_shared.h"
#include "support/gpu_test.h"

using namespace vknerf;

namespace {

bool synchronizationValidationOn() {
  const char* enables = std::getenv("VK_LAYER_ENABLES");
  return std::getenv("VKNERF_VALIDATION") && enables &&
         std::strstr(enables, "VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT");
}

// A context of its own, so that the hazard's messages are counted there and not in the shared one.
struct HazardRun {
  std::shared_ptr<Context> ctx;
  uint32_t messages = 0;
  explicit HazardRun(bool barrier) {
    ContextOptions o;
    o.validation = true;
    ctx = Context::create(o);
    using Push = glsl::RaysPush;
    Push push{{-1, -1, -1, 0}, {1, 1, 1, 0}, 0, 0, 0, 64};
    gpu::Kernel rays(*ctx, {gpu::shaders::rays, {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage},
                            sizeof(Push), {}});
    Camera cam;
    cam.fx = cam.fy = 10;
    cam.width = cam.height = 8;
    cam.cx = cam.cy = 4;
    cam.c2w[11] = 3;
    auto cams = gpu::Buffer::of(*ctx, nerf::packCameras(std::span<const Camera>(&cam, 1)));
    gpu::Buffer out(*ctx, 64 * 8 * 4), ids(*ctx, 64 * nerf::kPixelIdBytes);
    gpu::Recorder rec(*ctx);
    rec.begin();
    if (barrier) {
      rec.dispatch(rays, {cams, out, ids}, push, 1);
      rec.fill(out, 0);
    } else {
      // The same two commands recorded by hand, as a Recorder without its barrier would.
      VkCommandBuffer cmd = rec.commandBuffer();
      const gpu::BufferRange bindings[] = {cams, out, ids};
      VkDescriptorSet set = rays.descriptorSet(bindings);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, rays.pipeline());
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, rays.layout(), 0, 1, &set, 0, nullptr);
      vkCmdPushConstants(cmd, rays.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
      vkCmdDispatch(cmd, 1, 1, 1);
      vkCmdFillBuffer(cmd, out.handle(), 0, VK_WHOLE_SIZE, 0);
    }
    rec.end();
    rec.submitAndWait();
    messages = ctx->validationMessages();
  }
};

TEST(Synchronization, AMissingBarrierIsReportedAndTheRecordersBarrierIsNot) {
  if (!synchronizationValidationOn())
    GTEST_SKIP() << "synchronization validation is off (VKNERF_VALIDATION and VK_LAYER_ENABLES, as ctest sets them)";
  EXPECT_GT(HazardRun(false).messages, 0u) << "two unsynchronized writes went unreported";
  EXPECT_EQ(HazardRun(true).messages, 0u);
}

}  // namespace

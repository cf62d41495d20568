// The Vulkan host: device selection, adopting a caller's device, validation counting, limits.
#include <cstdlib>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/kernels/kernel.h"
#include "gpu/dispatch/recorder.h"
#include "support/error_message.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "nerf/rays/rays.h"
#include "rays/rays_shared.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

class ContextTest : public test::GpuTest {};

// A caller-owned instance and device, as an embedding application would have.
struct CallerDevice {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t family = 0;
  CallerDevice() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ci.pApplicationInfo = &app;
    EXPECT_EQ(vkCreateInstance(&ci, nullptr, &instance), VK_SUCCESS);
    uint32_t n = 1;
    vkEnumeratePhysicalDevices(instance, &n, &physical);
    uint32_t nf = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &nf, nullptr);
    std::vector<VkQueueFamilyProperties> fams(nf);
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &nf, fams.data());
    for (uint32_t i = 0; i < nf; ++i)
      if (fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
        family = i;
        break;
      }
    float prio = 1;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = family;
    qi.queueCount = 1;
    qi.pQueuePriorities = &prio;
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    EXPECT_EQ(vkCreateDevice(physical, &di, nullptr, &device), VK_SUCCESS);
    vkGetDeviceQueue(device, family, 0, &queue);
  }
  ~CallerDevice() {
    vkDestroyDevice(device, nullptr);
    vkDestroyInstance(instance, nullptr);
  }
};

}  // namespace

TEST_F(ContextTest, PicksAUsableDeviceAndDescribesIt) {
  auto devices = Context::listDevices();
  ASSERT_FALSE(devices.empty());
  EXPECT_FALSE(ctx().deviceName().empty());
  EXPECT_NE(ctx().describe().find(ctx().deviceName()), std::string::npos);
  EXPECT_GE(ctx().properties().apiVersion, VK_API_VERSION_1_2);
}

TEST_F(ContextTest, UnknownDeviceNameIsAClearError) {
  try {
    Context::create({"no-such-device-xyz", false});
    FAIL() << "expected vknerf::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-device-xyz"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Context::create({"97", false}), Error);  // index out of range
}

TEST_F(ContextTest, AdoptedDeviceRunsKernelsAndIsNotDestroyed) {
  CallerDevice caller;
  {
    auto adopted = Context::adopt({caller.instance, caller.physical, caller.device, caller.family, caller.queue, false});
    EXPECT_FALSE(adopted->owned());
    nerf::RayGeneration gen(*adopted);
    Camera cam;
    cam.fx = cam.fy = 4;
    cam.width = cam.height = 4;
    cam.cx = cam.cy = 2;
    cam.c2w[11] = 3;
    auto cams = nerf::packCameras(std::span<const Camera>(&cam, 1));
    auto camBuf = gpu::Buffer::of(*adopted, cams);
    gpu::Buffer rays(*adopted, 16 * nerf::kRayBytes), ids(*adopted, 16 * nerf::kPixelIdBytes);
    test::submitOnce(*adopted, [&](gpu::Recorder& rec) {
      gen.recordImage(rec, camBuf, {0, 0, 16}, {Aabb{}, 0}, {rays, ids});
    });
    auto r = rays.download<float>(16 * 8);
    EXPECT_GT(r[3], 1.9f);  // enters the unit box near z = 1
  }
  // The context is gone; the caller's device must still work.
  VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence;
  ASSERT_EQ(vkCreateFence(caller.device, &fi, nullptr, &fence), VK_SUCCESS);
  vkDestroyFence(caller.device, fence, nullptr);
  EXPECT_EQ(vkQueueWaitIdle(caller.queue), VK_SUCCESS);
}

TEST_F(ContextTest, AdoptRejectsMissingHandles) {
  EXPECT_THROW(Context::adopt({}), Error);
}

TEST_F(ContextTest, ValidationLayerMessagesAreCounted) {
  // A second context with validation, then a deliberate misuse: the counter must see it, so a
  // clean suite really means "no messages", not "no layer".
  if (!std::getenv("VKNERF_VALIDATION")) GTEST_SKIP() << "VKNERF_VALIDATION not set";
  auto probe = Context::create({"", true});
  ASSERT_TRUE(probe->validationEnabled());
  uint32_t before = probe->validationMessages();
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = 0;  // invalid: size must be > 0
  bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer b = VK_NULL_HANDLE;
  std::fprintf(stderr, "(the next validation error is deliberate)\n");
  vkCreateBuffer(probe->device(), &bi, nullptr, &b);
  if (b) vkDestroyBuffer(probe->device(), b, nullptr);
  EXPECT_GT(probe->validationMessages(), before);
}

TEST_F(ContextTest, BindingOverStorageRangeIsRejected) {
  nerf::RayGeneration gen(ctx());
  const VkDeviceSize limit = ctx().properties().limits.maxStorageBufferRange;
  if (limit >= (VkDeviceSize(1) << 31)) GTEST_SKIP() << "device storage range is too large to exceed cheaply";
  gpu::Buffer big(ctx(), limit + 256), cams(ctx(), 80), ids(ctx(), 64);
  gpu::Recorder rec(ctx());
  rec.begin();
  EXPECT_THROW(gen.recordImage(rec, cams, {0, 0, 1}, {Aabb{}, 0}, {big, ids}), Error);
  // The same buffer bound at an offset, within the limit, is accepted.
  EXPECT_NO_THROW(gen.recordImage(rec, cams, {0, 0, 1}, {Aabb{}, 0}, {gpu::BufferRange(big, 256, limit), ids}));
  rec.end();
}

TEST_F(ContextTest, BufferRoundTripAndZero) {
  std::vector<float> v(1000);
  for (size_t i = 0; i < v.size(); ++i) v[i] = float(i) * 0.5f;
  auto b = gpu::Buffer::of(ctx(), v);
  EXPECT_EQ(b.download<float>(), v);
  b.zero();
  for (float x : b.download<float>()) ASSERT_EQ(x, 0.0f);
  gpu::Buffer empty(ctx(), 0);
  EXPECT_TRUE(empty.valid());
  EXPECT_TRUE(empty.download<float>().empty());
}

// Out of memory names the buffer and its size, so that a caller can say what to lower. 2^50
// bytes is more than any device offers (and more than Vulkan implementations accept as a buffer).
TEST_F(ContextTest, OutOfMemoryNamesTheBufferAndItsSize) {
  const std::string msg = test::errorOf([&] { gpu::Buffer(ctx(), VkDeviceSize(1) << 50, "the test's buffer"); });
  EXPECT_MESSAGE_HAS(msg, "cannot allocate the test's buffer of 1073741824.0 MiB (1125899906842624 bytes)");
  EXPECT_MESSAGE_HAS(msg, "VK_ERROR_OUT_OF_");
}

TEST_F(ContextTest, IndirectDispatchReadsGroupCountsFromTheDevice) {
  // rays.comp asked for 1000 rays, but the indirect arguments allow 2 workgroups of 64: exactly
  // 128 rays are written, the rest keep their sentinel.
  using Push = glsl::RaysPush;
  Push push{{-1, -1, -1, 0}, {1, 1, 1, 0}, 0, 0, 0, 1000};
  gpu::Kernel rays(ctx(), {gpu::shaders::rays, {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage}, sizeof(Push), {}});
  Camera cam;
  cam.fx = cam.fy = 10;
  cam.width = cam.height = 40;
  cam.cx = cam.cy = 20;
  cam.c2w[11] = 3;
  auto camBuf = gpu::Buffer::of(ctx(), nerf::packCameras(std::span<const Camera>(&cam, 1)));
  auto out = gpu::Buffer::of(ctx(), std::vector<float>(1000 * 8, 7.0f));
  gpu::Buffer ids(ctx(), 1000 * nerf::kPixelIdBytes);
  auto args = gpu::Buffer::of(ctx(), std::vector<uint32_t>{0, 2, 1, 1});
  test::submitOnce(ctx(), [&](gpu::Recorder& rec) {
    EXPECT_THROW(rec.dispatchIndirect(rays, {camBuf, out, ids}, &push, sizeof push, args, 8, "rays"), Error);
    rec.dispatchIndirect(rays, {camBuf, out, ids}, &push, sizeof push, args, 4, "rays");
  });
  auto r = out.download<float>(1000 * 8);
  for (int i = 0; i < 1000; ++i) {
    if (i < 128)
      ASSERT_NE(r[8 * i + 6], 7.0f) << i;  // a direction component was written
    else
      ASSERT_EQ(r[8 * i + 6], 7.0f) << i;
  }
}

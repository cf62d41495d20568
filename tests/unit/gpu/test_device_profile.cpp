// Device profiles (src/gpu/device/device_profile.h): lavapipe behaving like other classes of device, and
// the limits every kernel and dispatch is checked against (src/gpu/kernels/kernel_limits.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "gpu/memory/buffer.h"
#include "gpu/device/device.h"
#include "gpu/device/device_profile.h"
#include "gpu/kernels/kernel.h"
#include "gpu/kernels/kernel_limits.h"
#include "gpu/device/physical_devices.h"
#include "gpu/dispatch/recorder.h"
#include "support/error_message.h"
#include "support/gpu_test.h"
#include "support/submit_once.h"
#include "vknerf/error.h"

using namespace vknerf;

namespace {

std::shared_ptr<Context> profiled(const std::string& name) {
  ContextOptions o;
  o.profile = name;
  o.validation = test::context().validationEnabled();
  return Context::create(o);
}

class DeviceProfileTest : public test::GpuTest {};

TEST_F(DeviceProfileTest, UnknownProfileIsAClearError) {
  const std::string msg = test::errorOf([] { profiled("radeon-9700"); });
  EXPECT_MESSAGE_HAS(msg, "unknown device profile 'radeon-9700'");
  EXPECT_MESSAGE_HAS(msg, "minimum, nvidia, amd-rdna2, intel-xe-lp, mali, apple");
}

// Every profile: its name in force, no limit above the profile's or the device's own, no alignment
// below either, the features its class lacks hidden, its memory model, and no validation message.
TEST_F(DeviceProfileTest, EachProfileImposesItsLimitsFeaturesAndMemory) {
  // The device as it is, even when the suite runs under a profile (VKNERF_DEVICE_PROFILE).
  const auto plain = profiled("none");
  const auto& own = plain->properties().limits;
  const auto& ownFeatures = gpu::device(*plain).features();
  EXPECT_EQ(plain->profile(), "");
  for (const auto& p : gpu::deviceProfiles()) {
    SCOPED_TRACE(p.name);
    auto c = profiled(p.name);
    const auto& dev = gpu::device(*c);
    const auto& l = c->properties().limits;
    EXPECT_EQ(c->profile(), p.name);
    for (int i = 0; i < 3; ++i)
      EXPECT_EQ(l.maxComputeWorkGroupCount[i], std::min(own.maxComputeWorkGroupCount[i], p.maxComputeWorkGroupCount[i]));
    EXPECT_EQ(l.maxStorageBufferRange, std::min(own.maxStorageBufferRange, p.maxStorageBufferRange));
    EXPECT_EQ(l.maxTexelBufferElements, std::min(own.maxTexelBufferElements, p.maxTexelBufferElements));
    EXPECT_EQ(l.maxPushConstantsSize, std::min(own.maxPushConstantsSize, p.maxPushConstantsSize));
    EXPECT_EQ(l.minStorageBufferOffsetAlignment, std::max(own.minStorageBufferOffsetAlignment, p.minStorageBufferOffsetAlignment));
    EXPECT_EQ(c->floatAtomics(), ownFeatures.bufferFloatAtomicAdd && p.floatAtomicAdd);
    EXPECT_EQ(dev.features().subgroupArithmetic, ownFeatures.subgroupArithmetic && p.subgroupArithmetic);
    EXPECT_EQ(dev.features().subgroupVote, ownFeatures.subgroupVote && p.subgroupVote);
    EXPECT_EQ(dev.unifiedMemory(), p.memory == gpu::MemoryModel::Unified);
    EXPECT_EQ(dev.hostCoherent(), p.hostCoherent);
    EXPECT_TRUE(dev.fillsNewBuffers());
    EXPECT_EQ(dev.texelsAsStorage(), l.maxTexelBufferElements < (1u << 24));
    const auto lines = c->capabilities();
    ASSERT_FALSE(lines.empty());
    EXPECT_MESSAGE_HAS(lines[0], p.name);
    EXPECT_EQ(c->validationMessages(), 0u);
  }
}

// A GPU's fresh memory holds whatever was there; a profile makes that NaN bytes, so a read before
// a write shows. zeros() still zeroes, and data round-trips through staging on the discrete model,
// with the flushes and invalidations non-coherent memory needs.
TEST_F(DeviceProfileTest, DiscreteNonCoherentBuffersStartAsNanAndRoundTrip) {
  auto c = profiled("minimum");
  gpu::Buffer fresh(*c, 4096);
  EXPECT_EQ(fresh.mapped(), nullptr);  // the host never maps device buffers on the discrete model
  for (uint32_t w : fresh.download<uint32_t>()) ASSERT_EQ(w, 0xFFFFFFFFu);
  float asFloat;
  const uint32_t bits = 0xFFFFFFFFu;
  std::memcpy(&asFloat, &bits, 4);
  EXPECT_TRUE(std::isnan(asFloat));
  auto zeros = gpu::Buffer::zeros(*c, 4096);
  for (uint32_t w : zeros.download<uint32_t>()) ASSERT_EQ(w, 0u);
  std::vector<float> v(3000);
  for (size_t i = 0; i < v.size(); ++i) v[i] = float(i) * 0.25f;
  auto b = gpu::Buffer::of(*c, v);
  EXPECT_EQ(b.download<float>(), v);
  EXPECT_EQ(b.download<float>(10, 400), std::vector<float>(v.begin() + 100, v.begin() + 110));
  EXPECT_EQ(c->validationMessages(), 0u);
}

TEST_F(DeviceProfileTest, UnifiedNonCoherentBuffersAreFlushedAndInvalidated) {
  auto c = profiled("mali");
  std::vector<uint32_t> v(777);
  for (size_t i = 0; i < v.size(); ++i) v[i] = uint32_t(i * 2654435761u);
  auto b = gpu::Buffer::of(*c, v);
  EXPECT_NE(b.mapped(), nullptr);
  EXPECT_FALSE(b.hostCoherent());
  EXPECT_EQ(b.download<uint32_t>(), v);
  EXPECT_EQ(c->validationMessages(), 0u);
}

TEST_F(DeviceProfileTest, MemoryTypesPreferTheLargestHeapAndFallBack) {
  const auto& dev = gpu::device(ctx());
  const auto& mp = dev.memoryProperties();
  const auto types = dev.memoryTypesFor(~0u, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  ASSERT_EQ(types.size(), mp.memoryTypeCount);  // every type is a fallback when nothing is required
  for (size_t i = 1; i < types.size(); ++i) {
    const auto a = mp.memoryTypes[types[i - 1]], b = mp.memoryTypes[types[i]];
    const bool la = a.propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, lb = b.propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    EXPECT_TRUE(la > lb || (la == lb && mp.memoryHeaps[a.heapIndex].size >= mp.memoryHeaps[b.heapIndex].size));
  }
  EXPECT_TRUE(dev.memoryTypesFor(0, 0).empty());
}

TEST_F(DeviceProfileTest, DispatchesPastTheGroupCountAreRefused) {
  const auto& l = ctx().properties().limits;
  EXPECT_NO_THROW(gpu::checkGroupCounts(l, "k", l.maxComputeWorkGroupCount[0], 1, 1));
  const std::string msg = test::errorOf([&] { gpu::checkGroupCounts(l, "k", 1, l.maxComputeWorkGroupCount[1] + 1u, 1); });
  EXPECT_MESSAGE_HAS(msg, "exceed the device's maxComputeWorkGroupCount[1]");
}

TEST_F(DeviceProfileTest, KernelsPastPushConstantBindingOrWorkgroupLimitsAreRefused) {
  gpu::KernelDesc d{gpu::shaders::rays, {gpu::Binding::Storage, gpu::Binding::Storage, gpu::Binding::Storage}, 64, {}};
  const auto size = gpu::spirvLocalSize(d.shader);
  EXPECT_EQ(size[0], 64u);  // shaders/rays/rays.comp
  EXPECT_EQ(size[1] * size[2], 1u);
  VkPhysicalDeviceLimits l = ctx().properties().limits;
  EXPECT_NO_THROW(gpu::checkKernelLimits(l, d));
  auto refused = [&](VkPhysicalDeviceLimits lower, const char* name) {
    EXPECT_MESSAGE_HAS(test::errorOf([&] { gpu::checkKernelLimits(lower, d); }), name);
  };
  VkPhysicalDeviceLimits push = l;
  push.maxPushConstantsSize = 32;
  refused(push, "maxPushConstantsSize");
  VkPhysicalDeviceLimits storage = l;
  storage.maxPerStageDescriptorStorageBuffers = 2;
  refused(storage, "maxPerStageDescriptorStorageBuffers");
  VkPhysicalDeviceLimits invocations = l;
  invocations.maxComputeWorkGroupInvocations = 32;
  refused(invocations, "maxComputeWorkGroupInvocations");
  VkPhysicalDeviceLimits align = l;
  align.minStorageBufferOffsetAlignment = 256;
  EXPECT_NO_THROW(gpu::checkBindingOffset(align, "k", 0, gpu::Binding::Storage, 512));
  EXPECT_MESSAGE_HAS(test::errorOf([&] { gpu::checkBindingOffset(align, "k", 0, gpu::Binding::Storage, 64); }),
                     "minStorageBufferOffsetAlignment 256");
}

// MoltenVK is listed only to an instance that asks for portability enumeration, and a device that
// lists the portability subset must have it enabled.
TEST_F(DeviceProfileTest, PortabilityEnumerationAndSubsetAreRequestedWhereOffered) {
  const auto plain = gpu::instanceRequest({"VK_KHR_surface"}, false);
  EXPECT_TRUE(plain.extensions.empty());
  EXPECT_EQ(plain.flags, 0u);
  const auto mac = gpu::instanceRequest({"VK_KHR_surface", VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME}, true);
  EXPECT_EQ(mac.flags, VkInstanceCreateFlags(VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR));
  auto has = [](const std::vector<const char*>& v, const char* name) {
    return std::any_of(v.begin(), v.end(), [&](const char* e) { return std::strcmp(e, name) == 0; });
  };
  EXPECT_TRUE(has(mac.extensions, VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME));
  EXPECT_TRUE(has(mac.extensions, VK_EXT_DEBUG_UTILS_EXTENSION_NAME));
  EXPECT_TRUE(has(gpu::deviceExtensionsFor({"VK_KHR_portability_subset"}, false), "VK_KHR_portability_subset"));
  EXPECT_FALSE(has(gpu::deviceExtensionsFor({}, false), "VK_KHR_portability_subset"));
  EXPECT_TRUE(has(gpu::deviceExtensionsFor({}, true), VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME));
}

}  // namespace

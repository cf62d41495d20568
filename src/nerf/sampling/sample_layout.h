#pragma once
// The sample layout every stage shares: vec2(t, delta) per sample, sorted by t within a ray;
// delta is the length of the segment the sample stands for, the last closing at the ray's t_far.
#include <vulkan/vulkan.h>

namespace vknerf::nerf {

constexpr VkDeviceSize kSampleBytes = 8;

}  // namespace vknerf::nerf

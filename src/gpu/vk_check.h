#pragma once
#include <vulkan/vulkan.h>

#include <string>

#include "vknerf/error.h"

namespace vknerf::gpu {

const char* resultName(VkResult r);

// Throws vknerf::Error naming the call and its result; device loss and out-of-memory are not recoverable.
inline void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw Error(std::string(what) + " failed: " + resultName(r));
}

}  // namespace vknerf::gpu

#define VKN_CHECK(call) ::vknerf::gpu::check((call), #call)
